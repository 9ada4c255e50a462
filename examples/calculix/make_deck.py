#!/usr/bin/env python3
"""Writes a CalculiX input deck for a rectangular bar of solid, shell or beam elements.

The bar spans x in [x0, x0 + length], y in [-width/2, width/2], z in [-thickness/2,
thickness/2] (SI units), meshed with structured elements of the type --element:
  - solids: nx x ny x nz bricks, C3D20R or C3D20 (20 nodes), C3D8 or C3D8I (8 nodes; C3D8I has
    incompatible bending modes, which ccx carries on three internal nodes per element);
  - shells: nx x ny elements S8R (8 nodes) or S4 (4 nodes) on the mid-plane z = 0, with the
    thickness as *SHELL SECTION;
  - beams: nx elements B32R (3 nodes) or B31 (2 nodes) on the axis y = z = 0, with a
    rectangular *BEAM SECTION of width (y) by thickness (z).
ccx expands shells and beams into solid elements with nodes of their own through the thickness
and around the section (docs/calculix.md, "Internal and expanded nodes"). The deck has the
steps that `flexref import-modes` reads (docs/calculix.md):

  1. *FREQUENCY: the lowest --modes eigenmodes, displacements to JOB.frd (*NODE FILE U), with
     the face x = x0 clamped (--boundary clamped: translations of solid nodes, translations and
     rotations of shell and beam nodes) or no boundary condition (--boundary free);
  2. *FREQUENCY, SOLVER=MATRIXSTORAGE after *BOUNDARY, OP=NEW: the stiffness and mass
     matrices of the free solid in JOB.sti, JOB.mas and JOB.dof.

With --spin OMEGA a prestressed frequency step is inserted between them (docs/calculix.md,
"Geometric stiffness"): a geometrically nonlinear *STATIC step under the centrifugal load of a
spin OMEGA (rad/s) about the z axis through the origin, then *FREQUENCY with PERTURBATION.

Node sets written: ROOT (the nodes at x = x0) and TIP (the nodes at x = x0 + length); TIP_EDGE
(the nodes of the tip on the mid-plane z = 0).

Usage: make_deck.py [options] -o JOB.inp
"""

import argparse
import sys


SOLIDS = ["C3D20R", "C3D20", "C3D8", "C3D8I"]
SHELLS = ["S8R", "S4"]
BEAMS = ["B32R", "B31"]


def node_number(i, j, k, nx, ny):
    """Node number of lattice point (i, j, k) of an (nx+1) x (ny+1) x (nz+1) lattice."""
    return 1 + i + (nx + 1) * (j + (ny + 1) * k)


def lattice(a, quadratic, dims):
    """Nodes {number: (x, y, z)} of the lattice of the first `dims` directions (x; x, y; x, y, z),
    with half steps when quadratic; serendipity: no face or volume centres."""
    step = 2 if quadratic else 1
    n = [step * a.nx, step * a.ny if dims > 1 else 0, step * a.nz if dims > 2 else 0]
    nodes = {}
    for k in range(n[2] + 1):
        for j in range(n[1] + 1):
            for i in range(n[0] + 1):
                if quadratic and (i % 2) + (j % 2) + (k % 2) > 1:
                    continue
                nodes[node_number(i, j, k, n[0], n[1])] = (
                    a.x0 + a.length * i / n[0],
                    -a.width / 2 + a.width * j / n[1] if dims > 1 else 0.0,
                    -a.thickness / 2 + a.thickness * k / n[2] if dims > 2 else 0.0,
                )
    return nodes, n


def mesh(a):
    """Nodes {number: (x, y, z)} and elements [node numbers] of the bar in --element."""
    quadratic = a.element in ("C3D20R", "C3D20", "S8R", "B32R")
    dims = 3 if a.element in SOLIDS else 2 if a.element in SHELLS else 1
    nodes, n = lattice(a, quadratic, dims)
    number = lambda i, j, k: node_number(i, j, k, n[0], n[1])
    elements = []
    if dims == 1:
        for i in range(a.nx):
            # B32R: end, middle, end (ccx/Abaqus order).
            elements.append([number(2 * i + d, 0, 0) for d in range(3)]
                            if quadratic else [number(i, 0, 0), number(i + 1, 0, 0)])
        return nodes, elements
    for k in range(a.nz if dims == 3 else 1):
        for j in range(a.ny):
            for i in range(a.nx):
                if not quadratic:
                    I, J, K = i, j, k
                    corners = [(I, J, K), (I + 1, J, K), (I + 1, J + 1, K), (I, J + 1, K)]
                    if dims == 3:
                        corners += [(p, q, K + 1) for p, q, _ in corners]
                    elements.append([number(*c) for c in corners])
                    continue
                I, J, K = 2 * i, 2 * j, 2 * k
                if dims == 2:
                    # S8R: corners, then mid-side nodes, counter-clockwise.
                    points = [(I, J, 0), (I + 2, J, 0), (I + 2, J + 2, 0), (I, J + 2, 0),
                              (I + 1, J, 0), (I + 2, J + 1, 0), (I + 1, J + 2, 0), (I, J + 1, 0)]
                else:
                    # CalculiX/Abaqus order: corners of the bottom face, of the top face,
                    # mid-edge nodes of the bottom face, of the top face, then of the vertical
                    # edges.
                    points = [(I, J, K), (I + 2, J, K), (I + 2, J + 2, K), (I, J + 2, K),
                              (I, J, K + 2), (I + 2, J, K + 2), (I + 2, J + 2, K + 2),
                              (I, J + 2, K + 2),
                              (I + 1, J, K), (I + 2, J + 1, K), (I + 1, J + 2, K), (I, J + 1, K),
                              (I + 1, J, K + 2), (I + 2, J + 1, K + 2), (I + 1, J + 2, K + 2),
                              (I, J + 1, K + 2),
                              (I, J, K + 1), (I + 2, J, K + 1), (I + 2, J + 2, K + 1),
                              (I, J + 2, K + 1)]
                elements.append([number(p, q, r) for p, q, r in points])
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
        # At most 16 entries per line (ccx): the element number and 15 nodes.
        out.write(f"{number}, " + ", ".join(map(str, e[:15])) + ("," if len(e) > 15 else "") + "\n")
        if len(e) > 15:
            out.write(", ".join(map(str, e[15:])) + "\n")
    node_set(out, "ROOT", [n for n, p in sorted(nodes.items()) if p[0] == a.x0])
    node_set(out, "TIP", [n for n, p in sorted(nodes.items()) if p[0] == x_end])
    node_set(out, "TIP_EDGE", [n for n, p in sorted(nodes.items()) if p[0] == x_end and p[2] == 0.0])
    out.write("*MATERIAL, NAME=MATERIAL\n*ELASTIC\n")
    out.write(f"{a.young!r}, {a.poisson!r}\n*DENSITY\n{a.density!r}\n")
    if a.element in SHELLS:
        out.write(f"*SHELL SECTION, ELSET=EALL, MATERIAL=MATERIAL\n{a.thickness!r}\n")
    elif a.element in BEAMS:
        # RECT: the thickness along the section's 1-axis (here y), then along its 2-axis (z).
        out.write("*BEAM SECTION, ELSET=EALL, MATERIAL=MATERIAL, SECTION=RECT\n")
        out.write(f"{a.width!r}, {a.thickness!r}\n0., 1., 0.\n")
    else:
        out.write("*SOLID SECTION, ELSET=EALL, MATERIAL=MATERIAL\n")
    clamped = a.boundary == "clamped"
    if clamped:
        out.write("*BOUNDARY\nROOT, 1, " + ("3" if a.element in SOLIDS else "6") + "\n")
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
    p.add_argument("--element", choices=SOLIDS + SHELLS + BEAMS, default="C3D20R")
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
