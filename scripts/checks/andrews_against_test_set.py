#!/usr/bin/env python3
"""Compares a flexref trajectory of scenes/andrews_squeezer.toml with the IVP test set's
reference solution at t = 0.03 (PSIDE, rtol = atol = 1e-14; docs/joints.md). Prints, per angle of
the test set, the value from the CSV, the reference and the difference; exits 1 when any angle
differs by more than --tolerance (default 1e-9 rad).
Usage: /usr/bin/python3 scripts/checks/andrews_against_test_set.py REF.csv [--tolerance T]"""
import csv
import math
import sys

REFERENCE = {  # the test set's y(0.03): beta, Theta, gamma, Phi, delta, Omega, epsilon
    'beta': 0.1581077119629904e+2, 'Theta': -0.1575637105984298e+2,
    'gamma': 0.4082224013073101e-1, 'Phi': -0.5347301163226948e+0,
    'delta': 0.5244099658805304e+0, 'Omega': 0.5347301163226948e+0,
    'epsilon': 0.1048080741042263e+1}
# Initial absolute angles (the scene's), from which the unwrapped angles are followed.
BETA0 = -0.0617138900142764496358948458001


def main():
    path = sys.argv[1]
    tolerance = 1e-9
    if '--tolerance' in sys.argv:
        tolerance = float(sys.argv[sys.argv.index('--tolerance') + 1])
    with open(path) as f:
        rows = [r for r in csv.reader(line for line in f if not line.startswith('#'))]
    header, data = rows[0], [list(map(float, r)) for r in rows[1:]]
    col = {name: i for i, name in enumerate(header)}
    angles = {}
    for k in range(1, 8):
        e0, e3 = col[f'K{k}.e0'], col[f'K{k}.e3']
        # The planar rotation angle 2 atan2(e3, e0), unwrapped along the output times (each body
        # turns less than pi between outputs: K1's 1140 rad/s x 1e-4 s = 0.11 rad).
        previous = None
        unwrapped = []
        for r in data:
            a = 2.0 * math.atan2(r[e3], r[e0])
            if previous is not None:
                a += 2.0 * math.pi * round((previous - a) / (2.0 * math.pi))
            unwrapped.append(a)
            previous = a
        angles[f'K{k}'] = unwrapped
    if abs(data[-1][0] - 0.03) > 1e-12:
        sys.exit(f'{path}: the last output time is {data[-1][0]}, not 0.03')
    last = {k: v[-1] for k, v in angles.items()}
    # The test set's coordinates from the absolute angles (Theta, Phi, Omega are relative).
    ours = {'beta': last['K1'], 'Theta': last['K2'] - last['K1'], 'gamma': last['K3'],
            'Phi': last['K4'] - last['K5'], 'delta': last['K5'], 'Omega': last['K6'] - last['K7'],
            'epsilon': last['K7']}
    worst = 0.0
    print(f'{"angle":8s} {"flexref":>22s} {"test set (PSIDE 1e-14)":>24s} {"difference":>11s}')
    for name, ref in REFERENCE.items():
        diff = ours[name] - ref
        worst = max(worst, abs(diff))
        print(f'{name:8s} {ours[name]:22.15e} {ref:24.15e} {diff:11.2e}')
    print(f'largest difference {worst:.2e} rad (tolerance {tolerance:g})')
    sys.exit(0 if worst <= tolerance else 1)


main()
