"""networkx's Dijkstra on the graphs and pairs that benches/search.rs exports.

Usage: python3 benches/search_networkx.py GRAPHS.json

Per graph: a DiGraph (parallel arcs become the cheapest of them), then one untimed pass
over the pairs (the warm-up, and the costs), then PASSES timed passes of
`single_source_dijkstra(G, s, target=t)` (cost and path, as the Rust side returns);
the median pass divided by the number of pairs, in microseconds. Prints JSON:
{"networkx": VERSION, "graphs": [{"label", "median_us", "costs"}]}, a cost null when
the target cannot be reached.
"""

import json
import statistics
import sys
import time

import networkx as nx


def graph(g):
    G = nx.DiGraph()
    G.add_nodes_from(range(g["nodes"]))
    for u, v, w in g["arcs"]:
        if not G.has_edge(u, v) or w < G[u][v]["weight"]:
            G.add_edge(u, v, weight=w)
    return G


def cost(G, s, t):
    try:
        length, _path = nx.single_source_dijkstra(G, s, target=t, weight="weight")
        return length
    except nx.NetworkXNoPath:
        return None


def main():
    with open(sys.argv[1]) as f:
        data = json.load(f)
    out = []
    for g in data["graphs"]:
        G = graph(g)
        pairs = g["pairs"]
        costs = [cost(G, s, t) for s, t in pairs]
        passes = []
        for _ in range(data["passes"]):
            start = time.perf_counter()
            for s, t in pairs:
                cost(G, s, t)
            passes.append(time.perf_counter() - start)
        median_us = statistics.median_low(passes) / len(pairs) * 1e6
        out.append({"label": g["label"], "median_us": median_us, "costs": costs})
    json.dump({"networkx": nx.__version__, "graphs": out}, sys.stdout)


if __name__ == "__main__":
    main()
