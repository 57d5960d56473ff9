#!/usr/bin/env python3
"""Writes the malformed databases of the `cellc import dualmanip` UI tests.

Each `CODE_what.db` is a small dual_manipulation database (the schema of the original
system) with one problem, which must make the import report CODE and nothing else.
Run from anywhere: `python3 tests/ui/import/make_dbs.py`. The output is deterministic, so
the committed files only change when this script does.
"""

import os
import sqlite3

HERE = os.path.dirname(os.path.abspath(__file__))

SCHEMA = {
    "Objects": "CREATE TABLE Objects (Id INTEGER PRIMARY KEY, Name TEXT, MeshPath TEXT, ObjectCenter TEXT)",
    "EndEffectors": "CREATE TABLE EndEffectors (Id INTEGER PRIMARY KEY, Name TEXT, Movable NUMERIC)",
    "Workspaces": "CREATE TABLE Workspaces (Id INTEGER PRIMARY KEY, Name TEXT)",
    "WorkspacesAdjacency": "CREATE TABLE WorkspacesAdjacency (id_source NUMERIC, id_target NUMERIC)",
    "Reachability": "CREATE TABLE Reachability (EndEffector_id NUMERIC, Workspace_id NUMERIC)",
    "WorkspaceGeometry": "CREATE TABLE WorkspaceGeometry (Workspace_id INTEGER PRIMARY KEY, Polygon TEXT)",
    "Grasps": "CREATE TABLE Grasps (Object_id NUMERIC, EndEffector_id NUMERIC, Grasp_id INTEGER PRIMARY KEY, Grasp_info BLOB, Grasp_name TEXT)",
    "Grasp_transitions": "CREATE TABLE Grasp_transitions (Source_id NUMERIC, Target_id NUMERIC)",
}


def base():
    """A correct database: a hand and a table over two workspaces, one cube."""
    return {
        "Objects": [(1, "cube", "package://objects/cube.stl", "0 0 0 0 0 0 1")],
        "EndEffectors": [(1, "hand", 1), (2, "table", 0)],
        "Workspaces": [(1, "Left"), (2, "Right")],
        "WorkspacesAdjacency": [(1, 2)],
        "Reachability": [(1, 1), (1, 2), (2, 1), (2, 2)],
        "WorkspaceGeometry": [(1, "0 0 1 0 1 1 0 1"), (2, "1 0 2 0 2 1 1 1")],
        "Grasps": [(1, 2, 11, "", "standing"), (1, 1, 12, "", "top")],
        "Grasp_transitions": [(11, 12), (12, 11)],
    }


def write(name, tables, schema=None):
    schema = dict(SCHEMA, **(schema or {}))
    path = os.path.join(HERE, name)
    if os.path.exists(path):
        os.remove(path)
    conn = sqlite3.connect(path)
    for table, rows in tables.items():
        conn.execute(schema[table])
        for row in rows:
            marks = ", ".join("?" for _ in row)
            conn.execute(f"INSERT INTO {table} VALUES ({marks})", row)
    conn.commit()
    conn.execute("VACUUM")
    conn.close()


def main():
    with open(os.path.join(HERE, "E0601_not_sqlite.db"), "w") as f:
        f.write("This is a text file, not an SQLite database.\n")

    t = base()
    del t["Grasp_transitions"]
    write("E0602_missing_table.db", t)

    t = base()
    t["Grasps"] = [(o, e, g, i) for (o, e, g, i, _) in t["Grasps"]]
    write("E0602_missing_column.db", t, {
        "Grasps": "CREATE TABLE Grasps (Object_id NUMERIC, EndEffector_id NUMERIC, Grasp_id INTEGER PRIMARY KEY, Grasp_info BLOB)",
    })

    t = base()
    t["Grasps"][1] = ("cube", 1, 12, "", "top")
    write("E0602_text_id.db", t)

    t = base()
    t["Grasp_transitions"].append((12, 99))
    write("E0603_unknown_grasp.db", t)

    t = base()
    t["Grasps"].append((1, 7, 13, "", "side"))
    t["Grasp_transitions"] += [(11, 13), (13, 11)]
    write("E0603_unknown_end_effector.db", t)

    t = base()
    t["Objects"].append((2, "ball", "package://objects/ball.stl", "0 0 0 0 0 0 1"))
    t["Grasps"] += [(2, 2, 21, "", "resting"), (2, 1, 22, "", "top")]
    t["Grasp_transitions"] += [(21, 22), (22, 21), (12, 21)]
    write("E0604_cross_object.db", t)

    t = base()
    t["Workspaces"].append((2, "Middle"))
    write("E0605_duplicate_id.db", t, {
        "Workspaces": "CREATE TABLE Workspaces (Id INTEGER, Name TEXT)",
    })

    t = base()
    t["EndEffectors"][0] = (1, "hand", 2)
    write("E0606_movable_two.db", t)

    t = base()
    t["EndEffectors"].append((3, "bin", 0))
    t["Reachability"].append((3, 2))
    t["Grasps"].append((1, 3, 13, "", "in_bin"))
    t["Grasp_transitions"] += [(11, 13), (12, 13), (13, 12)]
    write("E0607_fixed_to_fixed.db", t)

    t = base()
    t["Workspaces"].append((3, "Far"))
    write("E0608_unreached_workspace.db", t)

    t = base()
    t["EndEffectors"].append((3, "bin", 0))
    write("E0608_reaches_nothing.db", t)

    t = base()
    t["WorkspacesAdjacency"].append((2, 2))
    write("E0609_self_adjacency.db", t)

    t = base()
    t["Workspaces"].append((3, "Far"))
    t["Reachability"].append((2, 3))
    t["WorkspacesAdjacency"].append((2, 3))
    write("E0609_useless_adjacency.db", t)

    t = base()
    t["WorkspacesAdjacency"] = []
    write("E0609_no_adjacency.db", t)


if __name__ == "__main__":
    main()
