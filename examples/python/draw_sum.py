#!/usr/bin/env python3
"""Draws A, B and their Minkowski sum A (+) B, each facet a polygon of its loop.

Usage: python3 examples/python/draw_sum.py [--out sum.png]

A is a box, B a turned icosahedron; the sum's facets come back as flat arrays (loop_start,
loop_vertex), and each carries the support pair (i, j) of A's vertex i and B's vertex j.
"""
import argparse

import matplotlib

matplotlib.use("Agg")  # files, not windows: runs on a server
import matplotlib.pyplot as plt
import numpy as np
from mpl_toolkits.mplot3d.art3d import Poly3DCollection

import minksum

PHI = (1 + 5 ** 0.5) / 2


def polygons(vertices, loop_start, loop_vertex):
    return [vertices[loop_vertex[loop_start[f]:loop_start[f + 1]]] for f in range(len(loop_start) - 1)]


def shape_polygons(shape, pose):
    """A shape's faces, placed by a 4x4 pose."""
    planes, start, loops = shape.faces
    return polygons(shape.vertices @ pose[:3, :3].T + pose[:3, 3], start, loops)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default="sum.png", help="the drawing (PNG)")
    args = parser.parse_args()
    a = minksum.Shape.box((1.0, 0.6, 0.4))
    ico = np.array([p for s in (-1, 1) for u in (-PHI, PHI) for p in ((0, s, u), (s, u, 0), (u, 0, s))], float) * 0.5
    b = minksum.Shape.from_points(ico)
    turn = np.eye(4)
    c, s = np.cos(0.5), np.sin(0.5)
    turn[:3, :3] = [[c, 0, s], [0, 1, 0], [-s, 0, c]]
    total = minksum.minkowski_sum(a, None, b, turn)

    fig = plt.figure(figsize=(12, 4.5))
    scenes = [("A: a box", shape_polygons(a, np.eye(4))), ("B: an icosahedron, turned", shape_polygons(b, turn)),
              (f"A (+) B: {total.V} vertices, {total.E} edges, {total.F} facets", polygons(total.vertices, total.loop_start, total.loop_vertex))]
    for k, (title, faces) in enumerate(scenes):
        ax = fig.add_subplot(1, 3, k + 1, projection="3d")
        ax.add_collection3d(Poly3DCollection(faces, facecolor=plt.cm.viridis(0.3 + 0.3 * k), edgecolor="k", linewidth=0.5, alpha=0.8))
        ax.set_xlim(-2, 2), ax.set_ylim(-2, 2), ax.set_zlim(-2, 2)
        ax.set_box_aspect((1, 1, 1))
        ax.set_title(title, fontsize=10)
    plt.tight_layout()
    plt.savefig(args.out, dpi=120)
    print(f"{args.out}: A with {len(a.vertices)} vertices, B with {len(b.vertices)}, A (+) B with {total.F} facets")


if __name__ == "__main__":
    main()
