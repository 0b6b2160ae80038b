"""Prototype of the stability verdict (see bench/results/stability_design.md): the
constrained Hessian of a discretised total potential energy of a Kirchhoff tendon robot,
at a solution of the shooting solver.

Coordinates: the body-frame rotation perturbation of every node (the base clamped);
positions follow by integrating the elements' midpoint directions (inextensible,
unshearable: no constraint needed). Energy: bending and torsion per element
(log of the relative rotation), dead point and distributed loads (through the force
beyond each element), tendons: tension x polyline length through their eyelets (the
tension a Lagrange multiplier for an inextensible displacement-controlled tendon, whose
length gradient becomes a constraint; EA/l (l - l0)^2 / 2 for an extensible one).
Element Hessians by central second differences, assembled block-tridiagonally; dense
eigenvalues here (a prototype: slow, clear).

    .venv/bin/python bench/stability_prototype.py
"""

import math

import numpy as np

import tendonrod as tr


def hat(w):
    return np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])


def expm(w):
    th = np.linalg.norm(w)
    K = hat(w)
    if th < 1e-12:
        return np.eye(3) + K + 0.5 * K @ K
    return np.eye(3) + math.sin(th) / th * K + (1 - math.cos(th)) / th**2 * K @ K


def logm(Q):
    c = max(-1.0, min(1.0, (np.trace(Q) - 1) / 2))
    th = math.acos(c)
    v = np.array([Q[2, 1] - Q[1, 2], Q[0, 2] - Q[2, 0], Q[1, 0] - Q[0, 1]]) / 2
    if th < 1e-8:
        return v
    return v * th / math.sin(th)


class Discrete:
    def __init__(self, sol, N=40):
        sc = sol.scene
        rob = sc.robot
        rod = rob.rod
        self.L = L = rod.length
        self.N = N
        self.s = np.linspace(0, L, N + 1)
        self.h = L / N
        st = sol.at(self.s)
        self.R = st.rotation.copy()
        self.K = np.diag([rod.bending_stiffness, rod.bending_stiffness, rod.torsional_stiffness])
        # dead loads: total force beyond each element (point loads at nodes, distributed)
        self.Fd = np.zeros((N, 3))  # force acting on element k's direction term
        for ld in sc.point_loads:
            j = int(round(ld.s / self.h))
            assert abs(j * self.h - ld.s) < 1e-9 * L, "point loads at nodes only"
            assert np.allclose(ld.moment, 0), "no point moments in the prototype"
            for k in range(j):
                self.Fd[k] += np.asarray(ld.force)
        f = np.asarray(sc.distributed_force)
        for k in range(N):
            # p at the element's nodes contributes with trapezoid weights: the distributed
            # load beyond element k acts on d_k through all nodes downstream
            beyond = L - self.s[k + 1] + self.h / 2  # trapezoid: half of element k itself
            self.Fd[k] += f * beyond
        # tendons
        self.tendons = []
        for i, t in enumerate(rob.tendons):
            tau = float(sol.tension[i])
            end = rob.tendon_end(i)
            kend = int(round(end / self.h))
            assert abs(kend * self.h - end) < 1e-9 * L
            disp = sc.displacement[i] is not None
            kappa = None
            if disp and tau > 0:
                if math.isinf(t.EA):
                    kappa = math.inf
                else:
                    kappa = t.EA / (t.end if False else end)  # rest length ~ t (no pretension)
            self.tendons.append(
                dict(b=t.offset, a=t.slope, phi=t.angle, tau=tau, kend=kend, disp=disp, kappa=kappa)
            )

    def r(self, t, s):
        rho = t["b"] + t["a"] * s
        return np.array([rho * math.cos(t["phi"]), rho * math.sin(t["phi"]), 0.0])

    def element_energy(self, k, ek, ek1, with_tension=True):
        """Energy terms of element k as a function of the node perturbations (body-frame
        rotation vectors) of its nodes k, k+1 (node 0 is clamped: ek ignored there)."""
        Rk = self.R[k] @ expm(ek) if k > 0 else self.R[0]
        Rk1 = self.R[k + 1] @ expm(ek1)
        Q = Rk.T @ Rk1
        w = logm(Q)
        u = w / self.h
        E = 0.5 * self.h * u @ self.K @ u
        d = Rk @ expm(0.5 * w) @ np.array([0, 0, 1.0])
        E -= self.h * self.Fd[k] @ d
        if with_tension:
            for t in self.tendons:
                if k < t["kend"] and t["tau"] > 0:
                    c = self.h * d + Rk1 @ self.r(t, self.s[k + 1]) - Rk @ self.r(t, self.s[k])
                    E += t["tau"] * np.linalg.norm(c)
        return E

    def chord_len(self, t, k, ek, ek1):
        Rk = self.R[k] @ expm(ek) if k > 0 else self.R[0]
        Rk1 = self.R[k + 1] @ expm(ek1)
        w = logm(Rk.T @ Rk1)
        d = Rk @ expm(0.5 * w) @ np.array([0, 0, 1.0])
        c = self.h * d + Rk1 @ self.r(t, self.s[k + 1]) - Rk @ self.r(t, self.s[k])
        return np.linalg.norm(c)

    def hessian(self, eps=1e-5):
        N = self.N
        n = 3 * N  # nodes 1..N
        H = np.zeros((n, n))
        for k in range(N):
            idx = ([3 * (k - 1) + c for c in range(3)] if k > 0 else []) + [
                3 * k + c for c in range(3)
            ]
            nv = len(idx)
            off = 3 if k > 0 else 0

            def f(x):
                ek = x[:3] if k > 0 else np.zeros(3)
                ek1 = x[off : off + 3]
                return self.element_energy(k, ek, ek1)

            x0 = np.zeros(nv)
            He = np.zeros((nv, nv))
            for a in range(nv):
                for b in range(a, nv):

                    def ev(sa, sb):
                        x = x0.copy()
                        x[a] += sa * eps
                        x[b] += sb * eps
                        return f(x)

                    if a == b:
                        v = (ev(1, 0) - 2 * f(x0) + ev(-1, 0)) / eps**2
                    else:
                        v = (ev(1, 1) - ev(1, -1) - ev(-1, 1) + ev(-1, -1)) / (4 * eps**2)
                    He[a, b] = He[b, a] = v
            for a in range(nv):
                for b in range(nv):
                    H[idx[a], idx[b]] += He[a, b]
        cons = []
        for t in self.tendons:
            if t["kappa"] is None:
                continue
            g = np.zeros(n)
            for k in range(t["kend"]):
                idx = ([3 * (k - 1) + c for c in range(3)] if k > 0 else []) + [
                    3 * k + c for c in range(3)
                ]
                nv = len(idx)
                off = 3 if k > 0 else 0
                for a in range(nv):

                    def cl(sa):
                        x = np.zeros(nv)
                        x[a] += sa * eps
                        ek = x[:3] if k > 0 else np.zeros(3)
                        return self.chord_len(t, k, ek, x[off : off + 3])

                    g[idx[a]] += (cl(1) - cl(-1)) / (2 * eps)
            if math.isinf(t["kappa"]):
                cons.append(g)
            else:
                H += t["kappa"] * np.outer(g, g)
        return H, np.array(cons)


def stability(sol, N=40):
    """(margin, index): the smallest eigenvalue of the constrained Hessian in the norm
    (1/L) int |dtheta|^2 ds (trapezoid weights), scaled by EI/L; and the number of
    negative eigenvalues (the Morse index)."""
    D = Discrete(sol, N)
    H, C = D.hessian()
    EI, L = sol.scene.robot.rod.bending_stiffness, sol.scene.robot.rod.length
    w = np.full(3 * N, D.h / L)
    w[-3:] *= 0.5  # the free end node carries half an element
    Wi = np.diag(1 / np.sqrt(w))
    H = Wi @ H @ Wi  # M^-1/2 H M^-1/2
    if len(C):
        C = C @ Wi
        q, _ = np.linalg.qr(C.T, mode="complete")
        Z = q[:, len(C) :]
        H = Z.T @ H @ Z
    ev = np.linalg.eigvalsh(H)
    return ev[0] / (EI / L), int(np.sum(ev < 0))


def fig17(F):
    rod = tr.Rod(0.2, 0.8e-3, 207e9, 79.6e9, kirchhoff=True)
    r = 0.01
    return tr.Scene(
        tr.Robot(rod, [tr.Tendon(offset=r)]),
        displacement=[r * math.pi / 2],
        loads=[tr.PointLoad(s=0.2, force=(0, 0, -F))],
    )


def run_tendons():
    import warnings

    warnings.simplefilter("ignore")
    for F in (0.2, 0.35, 0.36, 0.5):
        sol = tr.solve(fig17(F), options=tr.Options(force_spatial=True))
        lam, idx = stability(sol, 40)
        print(
            f"fig17 F={F}: tension {sol.tension[0]:.4f} slack {sol.slack[0]:.2e} tip z {sol.tip_position[2]:.4f}: margin {lam:+.4f} EI/L index {idx}"
        )
    # tension-controlled: the same robot pulled by the tension of the F=0.2 solution
    s02 = tr.solve(fig17(0.2), options=tr.Options(force_spatial=True))
    sc = tr.Scene(s02.scene.robot, tension=[float(s02.tension[0])], loads=s02.scene.loads)
    sol = tr.solve(sc, options=tr.Options(force_spatial=True))
    lam, idx = stability(sol, 40)
    print(f"fig17 tension-controlled tau={sol.tension[0]:.3f}: margin {lam:+.4f} index {idx}")


if __name__ == "__main__":
    import warnings

    warnings.simplefilter("ignore")
    rod = tr.Rod(0.25, 1.2e-3, 60e9, 23e9, kirchhoff=True)
    EI = rod.bending_stiffness
    L = 0.25
    Pe = math.pi**2 * EI / (4 * L**2)
    robot = tr.Robot(rod, [])
    for f in (0.5, 0.95, 0.99, 1.01, 1.05, 1.5, 3, 10, 41):
        sc = tr.Scene(robot, loads=[tr.PointLoad(s=L, force=(0, 0, -f * Pe))])
        sol = tr.solve(sc, options=tr.Options(force_spatial=True))
        for N in (20, 40):
            lam, idx = stability(sol, N)
            exact = (math.pi**2 / 4) * (1 - f)  # the first mode of the straight column
            print(
                f"straight P={f:5.2f}Pe N={N}: margin {lam:+.4f} EI/L (exact first mode {exact:+.4f}), index {idx}"
            )
    run_tendons()
