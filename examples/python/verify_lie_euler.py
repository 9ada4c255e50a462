"""Verify an integrator written in Python against flexref (docs/external.md, "Python").

Explicit Lie-Euler on the torque-free body of scenes/free_spin.toml (10 s of it), at four
steps; flexref computes the reference with its estimated error, measures each run under the
trajectory contract (only t, Euler parameters and angular velocity are given) and fits the
observed order. Run from the repository root:  PYTHONPATH=build/python python3 examples/python/verify_lie_euler.py
"""
import sys
import numpy as np
import flexref

scene = flexref.load_scene(sys.argv[1] if len(sys.argv) > 1 else "scenes/free_spin.toml")
J = np.diag([3.0, 4.0, 5.0])                         # the scene's body: inertia, W0, identity
W0, T = np.array([0.2, 0.3, 2.0]), 10.0
ref = flexref.reference(scene, rtol=1e-10)           # exact solution + estimated error


def lie_euler(h):
    """theta <- theta (x) exp(h W), W <- W + h J^-1 ((J W) x W); rows every output step."""
    q, W, every, rows = np.array([1.0, 0, 0, 0]), W0.copy(), round(scene.output_step / h), []
    for n in range(round(T / h) + 1):
        if n % every == 0:
            rows.append([n * h, *q, *W])
        a = h * np.linalg.norm(W)
        p = np.array([np.cos(a / 2), *(np.sin(a / 2) / np.linalg.norm(W) * W)])
        q = np.array([q[0]*p[0] - q[1:] @ p[1:], *(q[0]*p[1:] + p[0]*q[1:] + np.cross(q[1:], p[1:]))])
        q, W = q / np.linalg.norm(q), W + h * np.linalg.solve(J, np.cross(J @ W, W))
    c = np.array(rows).T
    return dict(zip(["t", "body.e0", "body.e1", "body.e2", "body.e3", "body.W1", "body.W2", "body.W3"], c))


result = flexref.convergence(ref, [(h, lie_euler(h)) for h in (0.02, 0.01, 0.005, 0.0025)],
                             label="lie_euler", claimed_order=1)
print(result["table"])
assert abs(result["observed_order"] - 1.0) < 0.1, result["observed_order"]
