#!/usr/bin/env python3
"""Writes an abstract line cell of N movable end-effectors with G grasps each (issue 17's
10^6-arc cell at the defaults 50 and 100): workspaces w0..wN in a row, bench i reaching
w_i, arm i reaching w_i and w_(i+1), every grasp of an arm exchanged with every grasp of
its right neighbour and with the benches it reaches.

    python3 benches/gen_abstract_line.py [N] [G] > /tmp/abstract1m.cell
"""
import sys

n = int(sys.argv[1]) if len(sys.argv) > 1 else 50
g = int(sys.argv[2]) if len(sys.argv) > 2 else 100
out = ["cell abstract_line {"]
out += [f"  workspace w{i}" for i in range(n + 1)]
out += [f"  adjacent w{i} w{i + 1}" for i in range(n)]
out += [f"  fixed bench{i} reaches w{i}" for i in range(n + 1)]
out += [f"  movable a{i} reaches w{i}, w{i + 1}" for i in range(n)]
out.append("  object part {")
out += [f"    grasp r{i} by bench{i}" for i in range(n + 1)]
out += [f"    grasp a{i}g{k} by a{i}" for i in range(n) for k in range(g)]
for i in range(n):
    arm = ", ".join(f"a{i}g{k}" for k in range(g))
    if i + 1 < n:
        right = ", ".join(f"a{i + 1}g{k}" for k in range(g))
        out += [f"    transition a{i}g{k} <-> {right}" for k in range(g)]
    out.append(f"    transition r{i} <-> {arm}")
    out.append(f"    transition r{i + 1} <-> {arm}")
out.append("  }")
out.append(f"  request across: part from bench0.r0 in w0 to bench{n}.r{n} in w{n}")
out.append("}")
print("\n".join(out))
