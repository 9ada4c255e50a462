#!/usr/bin/env python3
"""An integrator that flexref does not contain, verified through `flexref converge --external`.

A standalone program, as another code's integrator would be: it reads a flexref scene itself
(TOML, scenes/README.md), integrates the torque-free rotation of its free rigid bodies with a
fixed step, and writes the trajectory under flexref's trajectory contract (docs/external.md):
`t`, the Euler parameters and the body-frame angular velocity, in its own column order, plus a
column of its own (`step_count`, which flexref ignores and lists).

    python3 lie_euler.py SCENE DT OUTPUT [--order 1|2]

--order 1 (default): explicit Lie-Euler, first order,
    theta_{n+1} = theta_n (x) exp(h W_n),       W_{n+1} = W_n + h f(W_n),
--order 2: the explicit midpoint rule on the group (Runge-Kutta-Munthe-Kaas, second order),
    W_half = W_n + h/2 f(W_n),  theta_{n+1} = theta_n (x) exp(h W_half),  W_{n+1} = W_n + h f(W_half),
with Euler's equations f(W) = J^-1 ((J W) x W) and exp the unit quaternion of a rotation
vector. Only free rigid bodies without loads (torque-free motion, e.g. scenes/free_spin.toml).

Run it through flexref:
    flexref converge scenes/free_spin.toml --external \
        "python3 examples/external/lie_euler.py {scene} {dt} {output}" --dt 0.02 --levels 4
"""
import math
import sys
import tomllib


def fail(message):
    print(f"lie_euler.py: {message}", file=sys.stderr)
    sys.exit(2)


def inverse3(m):
    a, b, c = m[0]
    d, e, f = m[1]
    g, h, i = m[2]
    det = a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g)
    return [[(e * i - f * h) / det, (c * h - b * i) / det, (b * f - c * e) / det],
            [(f * g - d * i) / det, (a * i - c * g) / det, (c * d - a * f) / det],
            [(d * h - e * g) / det, (b * g - a * h) / det, (a * e - b * d) / det]]


def matvec(m, v):
    return [m[0][0] * v[0] + m[0][1] * v[1] + m[0][2] * v[2],
            m[1][0] * v[0] + m[1][1] * v[1] + m[1][2] * v[2],
            m[2][0] * v[0] + m[2][1] * v[1] + m[2][2] * v[2]]


def euler_rate(J, Jinv, W):
    """f(W) = J^-1 ((J W) x W): Euler's equations of a torque-free body."""
    L = matvec(J, W)
    return matvec(Jinv, [L[1] * W[2] - L[2] * W[1], L[2] * W[0] - L[0] * W[2],
                         L[0] * W[1] - L[1] * W[0]])


def compose_exp(q, phi):
    """q (x) exp(phi): the attitude after the body-frame rotation vector phi."""
    angle = math.sqrt(phi[0] ** 2 + phi[1] ** 2 + phi[2] ** 2)
    c = math.cos(0.5 * angle)
    s = 0.5 - angle * angle / 48.0 if angle < 1e-4 else math.sin(0.5 * angle) / angle
    p = (c, s * phi[0], s * phi[1], s * phi[2])
    r = (q[0] * p[0] - q[1] * p[1] - q[2] * p[2] - q[3] * p[3],
         q[0] * p[1] + q[1] * p[0] + q[2] * p[3] - q[3] * p[2],
         q[0] * p[2] - q[1] * p[3] + q[2] * p[0] + q[3] * p[1],
         q[0] * p[3] + q[1] * p[2] - q[2] * p[1] + q[3] * p[0])
    n = math.sqrt(sum(x * x for x in r))  # keep the parameters unit against round-off
    return [x / n for x in r]


def main(argv):
    args = [a for a in argv if not a.startswith("--order")]
    order = 1
    for k, a in enumerate(argv):
        if a.startswith("--order"):
            value = a.split("=", 1)[1] if "=" in a else argv[k + 1]
            order = int(value)
            if value in args:
                args.remove(value)
    if len(args) != 3 or order not in (1, 2):
        fail("usage: lie_euler.py SCENE DT OUTPUT [--order 1|2]")
    scene_path, h, output = args[0], float(args[1]), args[2]
    with open(scene_path, "rb") as f:
        scene = tomllib.load(f)
    for key in ("gravity", "load", "charge", "contact", "joint", "potential"):
        if key in scene:
            fail(f"{scene_path}: [{key}] is not supported: torque-free free bodies only")
    end_time = float(scene["scene"]["end_time"])
    output_step = float(scene["scene"]["output_step"])
    per_output = round(output_step / h)
    if per_output < 1 or abs(per_output * h - output_step) > 1e-9 * output_step:
        fail(f"the step {h!r} does not divide the output step {output_step!r}")
    bodies = []
    for b in scene["body"]:
        if b.get("motion", "free") != "free" or "beam" in b or "modal" in b:
            fail(f"body {b['name']}: only free rigid bodies are supported")
        J = b["inertia"]
        J = [[J[0], 0, 0], [0, J[1], 0], [0, 0, J[2]]] if not isinstance(J[0], list) else J
        bodies.append({"name": b["name"], "J": J, "Jinv": inverse3(J),
                       "q": list(b.get("orientation", [1.0, 0.0, 0.0, 0.0])),
                       "W": list(b.get("angular_velocity", [0.0, 0.0, 0.0]))})

    columns = ["step_count", "t"]
    for b in bodies:
        n = b["name"]
        columns += [f"{n}.W3", f"{n}.W1", f"{n}.W2", f"{n}.e3", f"{n}.e2", f"{n}.e1", f"{n}.e0"]
    rows = []

    def write_row(n, t):
        row = [str(n), repr(t)]
        for b in bodies:
            W, q = b["W"], b["q"]
            row += [repr(W[2]), repr(W[0]), repr(W[1]), repr(q[3]), repr(q[2]), repr(q[1]),
                    repr(q[0])]
        rows.append(",".join(row))

    n_steps = round(end_time / h)
    write_row(0, 0.0)
    for n in range(n_steps):
        for b in bodies:
            J, Jinv, W = b["J"], b["Jinv"], b["W"]
            f0 = euler_rate(J, Jinv, W)
            if order == 1:
                b["q"] = compose_exp(b["q"], [h * w for w in W])
                b["W"] = [W[i] + h * f0[i] for i in range(3)]
            else:
                half = [W[i] + 0.5 * h * f0[i] for i in range(3)]
                b["q"] = compose_exp(b["q"], [h * w for w in half])
                fh = euler_rate(J, Jinv, half)
                b["W"] = [W[i] + h * fh[i] for i in range(3)]
        if (n + 1) % per_output == 0 or n + 1 == n_steps:
            write_row(n + 1, (n + 1) * h)
    with open(output, "w") as f:
        f.write("# lie_euler.py order %d, h = %r\n" % (order, h))
        f.write(",".join(columns) + "\n")
        f.write("\n".join(rows) + "\n")


if __name__ == "__main__":
    main(sys.argv[1:])
