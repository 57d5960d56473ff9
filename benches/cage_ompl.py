"""The peer of benches/cage_motions.rs: OMPL's RRT-Connect (the `ompl` wheel from PyPI)
on the motions the bench hands it, in the same cage, and the median time.

The bench writes the problem as JSON (the path is the first argument; an optional second
one is OMPL's state validity checking resolution): the URDF it used (with where each mesh was found and the SRDF's disabled pairs), the arm's base
pose, its joint limits, the motions (start and goal joints), the
cage's boxes (centres and half extents, in the cell frame) and the hand's solids (boxes
in the tip frame, the `panda_gripper` of cells/robots/panda.cell). Collision checking is
python-fcl (FCL 0.7) on the same geometry cellc checks: the convex hull of each link's
collision mesh (cellc checks hulls too), the hand's two finger boxes on the tip, the
boxes fixed; self-collisions between links more than one joint apart unless the SRDF
disables the pair, as in cellc. Edges are checked OMPL's way, at states a fixed fraction
of the space's extent apart (`--resolution`, OMPL's default 1%), not proven free between
them as cellc's are.

Prints one line per motion and a summary line, `ompl median_ms MS success K/N`, which the
bench reads. Timed: RRT-Connect's solve and OMPL's path simplification, per seed.
"""

import json
import statistics
import sys
import time
import xml.etree.ElementTree as ET
from pathlib import Path

import fcl
import numpy as np
from ompl import base as ob
from ompl import geometric as og
from ompl import util as ou
from scipy.spatial import ConvexHull
from stl import mesh as stl_mesh


def rpy_matrix(r, p, y):
    cr, sr, cp, sp, cy, sy = np.cos(r), np.sin(r), np.cos(p), np.sin(p), np.cos(y), np.sin(y)
    return np.array(
        [
            [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
            [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
            [-sp, cp * sr, cp * cr],
        ]
    )


def transform(xyz, rpy):
    t = np.eye(4)
    t[:3, :3] = rpy_matrix(*rpy)
    t[:3, 3] = xyz
    return t


def axis_rotation(axis, angle):
    axis = np.asarray(axis, dtype=float)
    axis /= np.linalg.norm(axis)
    x, y, z = axis
    c, s = np.cos(angle), np.sin(angle)
    k = np.array([[0, -z, y], [z, 0, -x], [-y, x, 0]])
    t = np.eye(4)
    t[:3, :3] = np.eye(3) + s * k + (1 - c) * (k @ k)
    return t


def floats(text, default):
    return [float(v) for v in text.split()] if text else default


class Chain:
    """The serial chain from `base` to `tip` of a URDF, with each link's collision mesh
    hull as an fcl object."""

    def __init__(self, urdf_path, meshes, base, tip):
        root = ET.parse(urdf_path).getroot()
        joints = {j.find("child").get("link"): j for j in root.findall("joint")}
        chain = []
        link = tip
        while link != base:
            j = joints[link]
            chain.append(j)
            link = j.find("parent").get("link")
        chain.reverse()
        self.steps = []  # (fixed transform, axis or None, link name after)
        for j in chain:
            o = j.find("origin")
            fixed = transform(
                floats(o.get("xyz") if o is not None else None, [0, 0, 0]),
                floats(o.get("rpy") if o is not None else None, [0, 0, 0]),
            )
            axis = None
            if j.get("type") in ("revolute", "continuous"):
                a = j.find("axis")
                axis = floats(a.get("xyz") if a is not None else None, [1, 0, 0])
            self.steps.append((fixed, axis, j.find("child").get("link")))
        self.links = [base] + [s[2] for s in self.steps]
        self.shapes = {}
        for l in root.findall("link"):
            name = l.get("name")
            if name not in self.links:
                continue
            for c in l.findall("collision"):
                m = c.find("geometry/mesh")
                if m is None:
                    continue
                path = meshes[m.get("filename")]
                points = stl_mesh.Mesh.from_file(str(path)).vectors.reshape(-1, 3)
                hull = ConvexHull(points)
                verts = points[hull.vertices]
                index = {v: i for i, v in enumerate(hull.vertices)}
                faces = [[index[v] for v in s] for s in hull.simplices]
                flat = []
                for f in faces:
                    flat += [3] + f
                o = c.find("origin")
                local = transform(
                    floats(o.get("xyz") if o is not None else None, [0, 0, 0]),
                    floats(o.get("rpy") if o is not None else None, [0, 0, 0]),
                )
                shape = fcl.Convex(verts, len(faces), np.array(flat))
                self.shapes.setdefault(name, []).append((local, shape))

    def frames(self, q):
        """Each link's pose in the base frame, by name."""
        t = np.eye(4)
        out = {self.links[0]: t}
        k = 0
        for fixed, axis, child in self.steps:
            t = t @ fixed
            if axis is not None:
                t = t @ axis_rotation(axis, q[k])
                k += 1
            out[child] = t
        return out


def fcl_transform(t):
    return fcl.Transform(t[:3, :3], t[:3, 3])


class Checker:
    def __init__(self, problem):
        self.chain = Chain(
            problem["urdf"], problem["meshes"], problem["base_link"], problem["tip_link"]
        )
        self.base = np.array(problem["base_pose"])
        self.tip = problem["tip_link"]
        # Solids that move: link hulls, then the hand's boxes on the tip.
        self.solids = []  # (link, local, fcl object)
        for link in self.chain.links:
            for local, shape in self.chain.shapes.get(link, []):
                self.solids.append((link, local, fcl.CollisionObject(shape)))
        for b in problem["hand_boxes"]:
            local = np.array(b["pose"])
            box = fcl.Box(*[2 * h for h in b["half_extents"]])
            self.solids.append((self.tip, local, fcl.CollisionObject(box)))
        # The hand kind's solids and the tip's links (the hand link is fixed to link7,
        # past the last joint) count as one body for the allowed pairs, as in cellc.
        order = {}
        frame = 0
        for i, link in enumerate(self.chain.links):
            if i > 0 and self.chain.steps[i - 1][1] is not None:
                frame += 1
            order[link] = frame
        self.frame = order
        disabled = set()
        for a, b in problem["disabled_collisions"]:
            disabled.add(frozenset((a, b)))
        self.self_pairs = []
        for i, (li, _, _) in enumerate(self.solids):
            for j in range(i + 1, len(self.solids)):
                lj = self.solids[j][0]
                if abs(order[li] - order[lj]) <= 1:
                    continue
                if frozenset((li, lj)) in disabled:
                    continue
                self.self_pairs.append((i, j))
        self.world = fcl.DynamicAABBTreeCollisionManager()
        self.boxes = []
        for b in problem["boxes"]:
            o = fcl.CollisionObject(
                fcl.Box(*[2 * h for h in b["half_extents"]]),
                fcl.Transform(np.array(b["centre"], dtype=float)),
            )
            self.boxes.append(o)
        self.world.registerObjects(self.boxes)
        self.world.setup()
        self.robot = fcl.DynamicAABBTreeCollisionManager()
        self.robot.registerObjects([s[2] for s in self.solids])
        self.robot.setup()
        self.checks = 0

    def valid(self, q):
        self.checks += 1
        frames = self.chain.frames(q)
        for link, local, obj in self.solids:
            obj.setTransform(fcl_transform(self.base @ frames[link] @ local))
        self.robot.update()
        request = fcl.CollisionRequest()
        data = fcl.CollisionData(request=request)
        self.robot.collide(self.world, data, fcl.defaultCollisionCallback)
        if data.result.is_collision:
            return False
        for i, j in self.self_pairs:
            result = fcl.CollisionResult()
            if fcl.collide(self.solids[i][2], self.solids[j][2], request, result):
                return False
        return True


def plan(checker, limits, start, goal, resolution):
    n = len(start)
    space = ob.RealVectorStateSpace(n)
    bounds = ob.RealVectorBounds(n)
    for i, (lo, hi) in enumerate(limits):
        bounds.setLow(i, lo)
        bounds.setHigh(i, hi)
    space.setBounds(bounds)
    ss = og.SimpleSetup(space)
    ss.setStateValidityChecker(lambda s: checker.valid([s[i] for i in range(n)]))
    si = ss.getSpaceInformation()
    si.setStateValidityCheckingResolution(resolution)
    a, b = space.allocState(), space.allocState()
    for i in range(n):
        a[i], b[i] = start[i], goal[i]
    ss.setStartAndGoalStates(a, b)
    ss.setPlanner(og.RRTConnect(si))
    ss.setup()
    begin = time.perf_counter()
    solved = ss.solve(10.0)
    exact = bool(solved) and ss.haveExactSolutionPath()
    if exact:
        ss.simplifySolution()
    return exact, (time.perf_counter() - begin) * 1e3


def main():
    problem = json.loads(Path(sys.argv[1]).read_text())
    resolution = float(sys.argv[2]) if len(sys.argv) > 2 else 0.01
    seeds = int(problem.get("seeds", 32))
    checker = Checker(problem)
    ou.setLogLevel(ou.LOG_ERROR)
    # Once, before any planner makes a generator: the runs are then reproducible.
    ou.RNG.setSeed(1)
    for m in problem["motions"]:
        for end in ("start", "goal"):
            if not checker.valid(m[end]):
                print(f"ompl {m['name']}: the {end} configuration collides here")
    times, successes, total = [], 0, 0
    for m in problem["motions"]:
        own = []
        for seed in range(seeds):
            ok, ms = plan(checker, problem["limits"], m["start"], m["goal"], resolution)
            own.append(ms)
            times.append(ms)
            successes += ok
            total += 1
        print(f"ompl {m['name']}: median {statistics.median(own):.2f} ms over {seeds} seeds")
    print(f"ompl median_ms {statistics.median(times):.3f} success {successes}/{total}")


if __name__ == "__main__":
    main()
