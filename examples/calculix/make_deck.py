#!/usr/bin/env python3
"""Writes a CalculiX input deck for a rectangular solid meshed with 20-node bricks.

The solid spans x in [x0, x0 + length], y in [-width/2, width/2], z in [-thickness/2,
thickness/2] (SI units), structured nx x ny x nz elements of type C3D20R (or C3D20). The deck
has the steps that `flexref import-modes` reads (docs/calculix.md):

  1. *FREQUENCY: the lowest --modes eigenmodes, displacements to JOB.frd (*NODE FILE U), with
     the face x = x0 clamped (--boundary clamped) or no boundary condition (--boundary free);
  2. *FREQUENCY, SOLVER=MATRIXSTORAGE after *BOUNDARY, OP=NEW: the stiffness and mass
     matrices of the free solid in JOB.sti, JOB.mas and JOB.dof.

With --spin OMEGA a prestressed frequency step is inserted between them (docs/calculix.md,
"Geometric stiffness"): a geometrically nonlinear *STATIC step under the centrifugal load of a
spin OMEGA (rad/s) about the z axis through the origin, then *FREQUENCY with PERTURBATION.

Node sets written: ROOT (the face x = x0) and TIP (the face x = x0 + length); TIP_EDGE (the
nodes of the tip face on the mid-plane z = 0).

Usage: make_deck.py [options] -o JOB.inp
"""

import argparse
import sys


def node_number(i, j, k, nx, ny):
    """Node number of lattice point (i, j, k) of the (2nx+1) x (2ny+1) x (2nz+1) lattice."""
    return 1 + i + (2 * nx + 1) * (j + (2 * ny + 1) * k)


def mesh(a):
    """Nodes {number: (x, y, z)} and elements [20 node numbers] of a 20-node brick mesh."""
    nx, ny, nz = a.nx, a.ny, a.nz
    nodes = {}
    for k in range(2 * nz + 1):
        for j in range(2 * ny + 1):
            for i in range(2 * nx + 1):
                if (i % 2) + (j % 2) + (k % 2) > 1:
                    continue  # serendipity: no face or volume centres
                nodes[node_number(i, j, k, nx, ny)] = (
                    a.x0 + a.length * i / (2 * nx),
                    -a.width / 2 + a.width * j / (2 * ny),
                    -a.thickness / 2 + a.thickness * k / (2 * nz),
                )
    elements = []
    for k in range(nz):
        for j in range(ny):
            for i in range(nx):
                I, J, K = 2 * i, 2 * j, 2 * k
                # CalculiX/Abaqus order: corners of the bottom face, of the top face, mid-edge
                # nodes of the bottom face, of the top face, then of the vertical edges.
                points = [(I, J, K), (I + 2, J, K), (I + 2, J + 2, K), (I, J + 2, K),
                          (I, J, K + 2), (I + 2, J, K + 2), (I + 2, J + 2, K + 2), (I, J + 2, K + 2),
                          (I + 1, J, K), (I + 2, J + 1, K), (I + 1, J + 2, K), (I, J + 1, K),
                          (I + 1, J, K + 2), (I + 2, J + 1, K + 2), (I + 1, J + 2, K + 2),
                          (I, J + 1, K + 2),
                          (I, J, K + 1), (I + 2, J, K + 1), (I + 2, J + 2, K + 1), (I, J + 2, K + 1)]
                elements.append([node_number(p, q, r, nx, ny) for p, q, r in points])
    return nodes, elements


def node_set(out, name, numbers):
    out.write(f"*NSET, NSET={name}\n")
    for start in range(0, len(numbers), 8):
        out.write(", ".join(str(n) for n in numbers[start:start + 8]) + "\n")


def write_deck(a, out):
    nodes, elements = mesh(a)
    x_end = a.x0 + a.length
    out.write("** " + " ".join(sys.argv) + "\n")
    out.write("*NODE, NSET=NALL\n")
    for n, (x, y, z) in sorted(nodes.items()):
        out.write(f"{n}, {x!r}, {y!r}, {z!r}\n")
    out.write(f"*ELEMENT, TYPE={a.element}, ELSET=EALL\n")
    for number, e in enumerate(elements, start=1):
        out.write(f"{number}, " + ", ".join(map(str, e[:15])) + ",\n")
        out.write(", ".join(map(str, e[15:])) + "\n")
    node_set(out, "ROOT", [n for n, p in sorted(nodes.items()) if p[0] == a.x0])
    node_set(out, "TIP", [n for n, p in sorted(nodes.items()) if p[0] == x_end])
    node_set(out, "TIP_EDGE", [n for n, p in sorted(nodes.items()) if p[0] == x_end and p[2] == 0.0])
    out.write("*MATERIAL, NAME=MATERIAL\n*ELASTIC\n")
    out.write(f"{a.young!r}, {a.poisson!r}\n*DENSITY\n{a.density!r}\n")
    out.write("*SOLID SECTION, ELSET=EALL, MATERIAL=MATERIAL\n")
    clamped = a.boundary == "clamped"
    if clamped:
        out.write("*BOUNDARY\nROOT, 1, 3\n")
    out.write(f"*STEP\n*FREQUENCY\n{a.modes}\n*NODE FILE\nU\n*END STEP\n")
    if a.spin > 0.0:
        out.write("*STEP, NLGEOM\n*STATIC\n*DLOAD\n")
        out.write(f"EALL, CENTRIF, {a.spin ** 2!r}, 0., 0., 0., 0., 0., 1.\n*END STEP\n")
        out.write(f"*STEP, PERTURBATION\n*FREQUENCY\n{a.modes}\n*NODE FILE\nU\n*END STEP\n")
    out.write("*STEP\n")
    if clamped or a.spin > 0.0:
        out.write("*BOUNDARY, OP=NEW\n")
    if a.spin > 0.0:
        out.write("*DLOAD, OP=NEW\n")
    out.write("*FREQUENCY, SOLVER=MATRIXSTORAGE\n*END STEP\n")


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--length", type=float, default=1.0, help="along x, m")
    p.add_argument("--width", type=float, default=0.06, help="along y, m")
    p.add_argument("--thickness", type=float, default=0.04, help="along z, m")
    p.add_argument("--x0", type=float, default=0.0, help="x of the root face, m")
    p.add_argument("--nx", type=int, default=10)
    p.add_argument("--ny", type=int, default=2)
    p.add_argument("--nz", type=int, default=2)
    p.add_argument("--element", choices=["C3D20R", "C3D20"], default="C3D20R")
    p.add_argument("--young", type=float, default=2.1e11, help="Pa")
    p.add_argument("--poisson", type=float, default=0.3)
    p.add_argument("--density", type=float, default=7800.0, help="kg/m^3")
    p.add_argument("--boundary", choices=["clamped", "free"], default="clamped")
    p.add_argument("--modes", type=int, default=10, help="eigenmodes of the frequency step")
    p.add_argument("--spin", type=float, default=0.0,
                   help="rad/s about z: add a prestressed frequency step (0: none)")
    p.add_argument("-o", "--output", required=True, help="the deck JOB.inp to write")
    a = p.parse_args()
    if min(a.nx, a.ny, a.nz, a.modes) < 1 or min(a.length, a.width, a.thickness) <= 0.0:
        p.error("element counts, modes and sizes must be positive")
    with open(a.output, "w", encoding="ascii") as out:
        write_deck(a, out)


if __name__ == "__main__":
    main()
