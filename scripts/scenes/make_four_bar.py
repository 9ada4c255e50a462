#!/usr/bin/env python3
"""Writes scenes/four_bar.toml: a Grashof crank-rocker four-bar in the x-y plane under gravity,
its bodies placed and set moving consistently with the loop closure (positions and velocities
exact to round-off, so the scene needs no projection). Run from the repository root:
    /usr/bin/python3 scripts/scenes/make_four_bar.py > scenes/four_bar.toml
Links: the ground A-D (d), the crank A-B (a), the coupler B-C (b), the rocker D-C (c); uniform
slender rods of 2 kg/m, frames at their first joint (A, B, D) with the body x axis along the link."""
import math

a, b, c, d = 0.1, 0.4, 0.3, 0.35     # m: crank, coupler, rocker, ground
rho = 2.0                            # kg/m
theta0, omega0 = math.pi / 2, 10.0   # crank angle from +x (rad) and rate (rad/s) at t = 0
g = 9.81

# Grashof: s + l < p + q with the crank the shortest link, so the crank turns fully and the
# transmission angle stays inside (0, pi): no singular configuration anywhere.
assert min(a, b, c, d) == a and a + b < c + d

A = (0.0, 0.0)
D = (d, 0.0)
B = (a * math.cos(theta0), a * math.sin(theta0))
# C: the intersection of the circles |C - B| = b and |C - D| = c above the line B-D.
bx, by = D[0] - B[0], D[1] - B[1]
e = math.hypot(bx, by)
x = (b * b - c * c + e * e) / (2 * e)
h = math.sqrt(b * b - x * x)
ux, uy = bx / e, by / e
C = (B[0] + x * ux - h * uy, B[1] + x * uy + h * ux)
if C[1] < 0:
    C = (B[0] + x * ux + h * uy, B[1] + x * uy - h * ux)
phi_b = math.atan2(C[1] - B[1], C[0] - B[0])   # coupler angle
phi_c = math.atan2(C[1] - D[1], C[0] - D[0])   # rocker angle
# Velocities: a w_a e(theta) + b w_b e(phi_b) = c w_c e(phi_c), e' = (-sin, cos).
# Solve b w_b (-sin phi_b, cos phi_b) - c w_c (-sin phi_c, cos phi_c) = -a w_a (-sin th, cos th).
m11, m12 = -b * math.sin(phi_b), c * math.sin(phi_c)
m21, m22 = b * math.cos(phi_b), -c * math.cos(phi_c)
r1, r2 = a * omega0 * math.sin(theta0), -a * omega0 * math.cos(theta0)
det = m11 * m22 - m12 * m21
w_b = (r1 * m22 - m12 * r2) / det
w_c = (m11 * r2 - r1 * m21) / det
vB = (-a * omega0 * math.sin(theta0), a * omega0 * math.cos(theta0))
# Closure residuals, for the record (round-off).
res = (B[0] + b * math.cos(phi_b) - D[0] - c * math.cos(phi_c),
       B[1] + b * math.sin(phi_b) - D[1] - c * math.sin(phi_c))
assert max(abs(r) for r in res) < 1e-15

def q(angle):
    return '[' + ', '.join(repr(v) for v in (math.cos(angle / 2), 0.0, 0.0, math.sin(angle / 2))) + ']'

def v(*xs):
    return '[' + ', '.join(repr(float(t)) for t in xs) + ']'

def inertia(m, L):
    # Slender rod about its centre of mass: axial 0 is not allowed (a body needs a positive
    # definite inertia), so the axial value is that of a square section of side L/20.
    side = L / 20
    return v(m * side * side / 6, m * L * L / 12, m * L * L / 12)

links = [('crank', a, theta0, A, (0.0, 0.0), omega0),
         ('coupler', b, phi_b, B, vB, w_b),
         ('rocker', c, phi_c, D, (0.0, 0.0), w_c)]
energy = 0.0
for name, L, ang, O, vO, w in links:
    m = rho * L
    gx, gy = O[0] + L / 2 * math.cos(ang), O[1] + L / 2 * math.sin(ang)
    vg = (vO[0] - w * L / 2 * math.sin(ang), vO[1] + w * L / 2 * math.cos(ang))
    energy += 0.5 * m * (vg[0] ** 2 + vg[1] ** 2) + 0.5 * m * L * L / 12 * w * w + m * g * gy

print(f'''# four_bar: a Grashof crank-rocker four-bar linkage swinging under gravity, on ideal revolute joints.
# Source: flexref's definition (the classical four-bar of every multibody text; IFToMM's benchmark
#   A02 is the singular parallelogram case, tests/constraint/mechanism_scenes_test.cpp). Generated
#   by scripts/scenes/make_four_bar.py, which places the links on the loop closure and sets their
#   rates from the crank's (consistent to round-off).
# Model: ground A-D = {d} m (A at the origin, D on +x), crank A-B = {a} m, coupler B-C = {b} m,
#   rocker D-C = {c} m, uniform slender rods of {rho} kg/m (I = m L^2/12 across, the axial value
#   of a square section of side L/20), each body's frame at its first joint with its x axis along
#   the link; four revolute joints about +z (A, B, C, D); gravity -9.81 m/s^2 along y. Grashof:
#   s + l = {a + b:g} < p + q = {c + d:g} with the crank the shortest link, so the crank can turn
#   fully and the transmission angle stays inside (0, pi): the mechanism never reaches a singular
#   configuration. In 3D the four revolute joints give 20 rows of rank 17 (three out-of-plane
#   rows repeat in the planar loop): 18 coordinates - 17 = 1 degree of freedom.
# Expected: the crank starts upright (theta = 90 deg) at {omega0} rad/s and keeps turning (its kinetic
#   energy exceeds the potential it must climb); the coupler and rocker follow the loop. No load
#   but gravity: the mechanical energy {energy!r} J (datum y = 0) is constant.

[scene]
name = "four_bar"
description = "Grashof crank-rocker four-bar under gravity on ideal revolute joints"
end_time = 2.0          # s
output_step = 1e-3      # s
gravity = [0.0, -9.81, 0.0]   # m/s^2''')
for name, L, ang, O, vO, w in links:
    m = rho * L
    print(f'''
[[body]]
name = "{name}"
mass = {m!r}                            # kg
inertia = {inertia(m, L)}   # kg*m^2 about the centre of mass, body axes
center_of_mass = {v(L / 2, 0, 0)}        # m, body frame: mid-link
position = {v(O[0], O[1], 0)}   # m, the frame origin at its first joint
orientation = {q(ang)}   # turned by {ang!r} rad about +z
velocity = {v(vO[0], vO[1], 0)}   # m/s, of the frame origin
angular_velocity = {v(0, 0, w)}   # rad/s, body frame
points = [{{ name = "tip", at = {v(L, 0, 0)} }}]''')

joints = [('A', 'crank', (0, 0), 'ground', (0.0, 0.0)),
          ('B', 'coupler', (0, 0), 'crank', (a, 0.0)),
          ('C', 'rocker', (c, 0), 'coupler', (b, 0.0)),
          ('D', 'rocker', (0, 0), 'ground', (d, 0.0))]
for name, ba, pa, bb, pb in joints:
    print(f'''
[[joint]]
name = "{name}"
model = "ideal"
kind = "revolute"
body_a = "{ba}"
point_a = {v(pa[0], pa[1], 0)}
body_b = "{bb}"
point_b = {v(pb[0], pb[1], 0)}
axis_a = [0.0, 0.0, 1.0]
axis_b = [0.0, 0.0, 1.0]''')
