#!/usr/bin/env python3
"""Loads two meshes, sweeps the second past the first and plots their exact distance.

Usage: python3 examples/python/distance_sweep.py [MESH_A MESH_B] [--out distance.png]

Without meshes it takes two Stanford bunnies from ../shared/data beside the source tree (else
two generated spheres). B passes A along x, turning about z, at 2,000 poses: one batch call,
over every core, from one (N, 4, 4) array of poses.
"""
import argparse
import os

import matplotlib

matplotlib.use("Agg")  # files, not windows: runs on a server
import matplotlib.pyplot as plt
import numpy as np

import minksum

HERE = os.path.dirname(os.path.abspath(__file__))
BUNNY = os.path.join(HERE, "..", "..", "..", "shared", "data", "bun_zipper_res3.ply")


def sphere_mesh(n=24):
    """A UV sphere of radius 0.08 (about a bunny's size), as vertices and triangles."""
    th, ph = np.meshgrid(np.linspace(0, np.pi, n), np.linspace(0, 2 * np.pi, 2 * n, endpoint=False), indexing="ij")
    v = 0.08 * np.column_stack([np.sin(th).ravel() * np.cos(ph).ravel(), np.sin(th).ravel() * np.sin(ph).ravel(), np.cos(th).ravel()])
    i, j = np.meshgrid(np.arange(n - 1), np.arange(2 * n), indexing="ij")
    a, b = (i * 2 * n + j).ravel(), (i * 2 * n + (j + 1) % (2 * n)).ravel()
    return v, np.vstack([np.column_stack([a, a + 2 * n, b]), np.column_stack([b, a + 2 * n, b + 2 * n])])


def load(path):
    return minksum.read_mesh(path) if path else (minksum.read_mesh(BUNNY) if os.path.exists(BUNNY) else sphere_mesh())


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("meshes", nargs="*", help="two mesh files (OFF, OBJ, PLY, STL)")
    parser.add_argument("--out", default="distance.png", help="the plot (PNG)")
    args = parser.parse_args()
    if len(args.meshes) not in (0, 2):
        parser.error("give two meshes, or none")
    va, ta = load(args.meshes[0] if args.meshes else None)
    vb, tb = load(args.meshes[1] if args.meshes else None)
    a, b = minksum.Mesh(va, ta), minksum.Mesh(vb, tb)
    size = np.ptp(va, axis=0).max() + np.ptp(vb, axis=0).max()
    centre_a, centre_b = va.mean(axis=0), vb.mean(axis=0)

    n = 2000
    x = np.linspace(-1.5, 1.5, n) * size
    poses = np.tile(np.eye(4), (n, 1, 1))
    angle = np.linspace(0, np.pi, n)
    poses[:, 0, 0], poses[:, 0, 1], poses[:, 1, 0], poses[:, 1, 1] = np.cos(angle), -np.sin(angle), np.sin(angle), np.cos(angle)
    poses[:, :3, 3] = centre_a - np.einsum("nij,j->ni", poses[:, :3, :3], centre_b) + np.column_stack([x, np.zeros(n), 0.2 * size * np.ones(n)])
    result = minksum.mesh_distance_batch(a, None, b, poses)

    plt.figure(figsize=(8, 4.5))
    plt.plot(x / size, result.distance, lw=1.5)
    plt.xlabel("offset of B along x (in A's and B's sizes)")
    plt.ylabel("exact distance")
    plt.title(f"B passing A: {len(ta):,} and {len(tb):,} triangles, {n:,} poses")
    plt.grid(alpha=0.3)
    plt.tight_layout()
    plt.savefig(args.out, dpi=120)
    print(f"{args.out}: the distance at {n} poses, from {result.distance.min():.4g} to {result.distance.max():.4g}")


if __name__ == "__main__":
    main()
