#!/usr/bin/env python3
"""architecture_graph.py GRAPH ARCHITECTURE_MD: docs/ARCHITECTURE.md cannot drift from the build.

GRAPH is <build>/stage_graph.txt, written by CMake from the stages' link libraries (the edges
`cmake --graphviz` draws between taskmap targets): "stage: dep, dep". Checks that the stage table
of ARCHITECTURE_MD (last column "depends on": the stages each links directly, or "—") lists
exactly these edges for every stage, and that no edge points back (the graph is acyclic and
follows the order of TASKMAP_STAGES). Exits 1 with every difference listed."""
import re
import sys


def read_graph(path):
    graph, order = {}, []
    for line in open(path, encoding="utf-8"):
        if ":" not in line:
            continue
        stage, deps = line.split(":", 1)
        graph[stage.strip()] = {d.strip() for d in deps.split(",") if d.strip()}
        order.append(stage.strip())
    return graph, order


def read_table(path):
    table = {}
    for line in open(path, encoding="utf-8"):
        m = re.match(r"^\|\s*`(\w+)`\s*\|(.*)\|\s*$", line)
        if not m:
            continue
        cells = [c.strip() for c in m.group(2).split("|")]
        deps = cells[-1]
        table[m.group(1)] = set() if deps in ("—", "-") else {
            re.sub(r"\s*\(.*\)$", "", d).strip() for d in deps.split(",")}
    return table


def main(graph_path, md_path):
    graph, order = read_graph(graph_path)
    table = read_table(md_path)
    errors = []
    for stage in order:
        if stage not in table:
            errors.append(f"{md_path}: stage '{stage}' is missing from the table")
        elif table[stage] != graph[stage]:
            errors.append(f"{md_path}: '{stage}' depends on {sorted(graph[stage])} in CMake, "
                          f"the table says {sorted(table[stage])}")
    for stage in table:
        if stage not in graph:
            errors.append(f"{md_path}: table lists '{stage}', which is not a stage of the build")
    rank = {s: i for i, s in enumerate(order)}
    for stage, deps in graph.items():
        for d in deps:
            if d not in rank or rank[d] >= rank[stage]:
                errors.append(f"edge {stage} -> {d} points back (TASKMAP_STAGES order: {order})")
    for e in errors:
        print(e)
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], sys.argv[2]))
