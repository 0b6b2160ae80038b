"""The outer iteration of :func:`tendonrod.actuate`: trust-region steps on the
linearisation of the current equilibrium (Levenberg-Marquardt for square and
least-squares targets, a composite-step sequential quadratic program for the least
change), every accepted iterate a converged solve.  Units as in
:mod:`tendonrod.actuation`: controls scaled by their solver scales, residuals
dimensionless."""

from __future__ import annotations

import numpy as np

from ._qp import solve_qp

# Consecutive rejected trust-region steps after which the iteration stops: the region has
# shrunk by 4^8 ~ 6e4 below the step refused first, so a step that still does not reduce
# the residual means none will (a least-squares point, e.g. at a tension bound).
_MAX_REJECTED = 8


# The first trust region (scaled controls): about a half turn of the tip.
_DELTA0 = 3.0

# The least change's stopping test (scaled controls): the step the linearised problem still
# asks for and its stationarity residual.  The forward-difference linearisation is good to
# ~1e-7 relative, so a tighter test chases its noise (steps of a few 1e-7 that the merit
# then refuses); 1e-6 is 1e-8 m of a displacement at a 10 mm offset.
_KKT_TOL = 1e-6


def _bfgs(H, s, y):
    """Powell's damped BFGS update of the Lagrangian's Hessian H (scaled units) for the
    step s and the change y of the Lagrangian's gradient: the constraints' curvature, which
    the plain least change (H = I) leaves out, so that the iteration converges
    superlinearly."""
    Hs = H @ s
    sHs = s @ Hs
    if not sHs > 0.0:
        return H
    sy = s @ y
    if sy < 0.2 * sHs:
        th = 0.8 * sHs / (sHs - sy)
        y = th * y + (1.0 - th) * Hs
        sy = s @ y
    return H - np.outer(Hs, Hs) / sHs + np.outer(y, y) / sy


class Iteration:
    """The outer iteration (see :func:`actuate`'s notes): every accepted iterate solved,
    every step from the linearisation of the current equilibrium."""

    def __init__(self, run, sol, r, D, c, c0, scale, is_tension, tau_scale, floor0, tol):
        self.run, self.c0, self.scale, self.tol = run, c0, scale, tol
        self.is_tension, self.tau_scale, self.floor0 = is_tension, tau_scale, floor0
        self.disp = run.scene.displacement_controlled()
        n = len(c)
        # per control: its tendon, whether it is a displacement, the rows of the trust
        # region and of the tension controls' bound (fixed; a slack tendon's row is added)
        self.idx = np.array(run.idx)
        self.disp_idx = np.array([self.disp[i] for i in run.idx], dtype=bool)
        self.eye = np.eye(n)
        self.bound = np.flatnonzero(is_tension)
        self.G0 = np.concatenate([self.eye, -self.eye, self.eye[self.bound]])
        self.H = np.eye(n)  # quasi-Newton Hessian of the Lagrangian (minimum change)
        self.nu = 0.0  # the merit's penalty on the target and tension floors
        # trust region of a step, scaled units: a unit turns the tip by about a radian; the
        # first steps may span a half turn (a bend that its linearisation predicts well),
        # the ratio test shrinks it where they do not
        self.delta = _DELTA0
        self.rejected = 0
        self.lam = self.mus = None
        self.optimal = False  # minimum change: a KKT point verified
        self.lsq = False  # square or least squares (set by iterate)
        self._set(c, sol, r, D)

    def _set(self, c, sol, r, D):
        self.c, self.sol, self.r, self._D = c, sol, r, D
        self._lin = self._rows = None
        self.slack_side = []  # tendons at their switch linearised on the slack side
        # within 1e4 tol of the target, iterate solves are polished (see _Run._solve_values)
        self.run.polish = bool(np.abs(r).max() <= 1e4 * self.tol)

    def _linearisation(self):
        """(A, T, side) at the current state, computed on first use (a state that meets
        the target in a square or least-squares problem needs none)."""
        if self._lin is None:
            self._to_taut_side()
            self._lin = self.run.linearize(self.sol, self._D, self._wanted_sides())
        return self._lin

    def _to_taut_side(self):
        """Slack displacement controls moved to the taut side of their switch, their slack
        taken up (a hair past it, 1e-12 of the scale), where the linearisation sees them
        act (on the slack side pulling one moves nothing, and the iteration would never
        pull it back): in least squares every slack one (steps then keep it from paying
        out again, see :meth:`lm`); in the least change those held taut (a finite floor,
        which then keeps them there), and those below their scene value, drawn toward it
        (up to the switch at most: a pull the least change gets for free).  A slack
        tendon moves nothing, so the target residual stays where it was."""
        cn = self.c.copy()
        for j, i in enumerate(self.run.idx):
            slack = self.sol.slack[i]
            if not (self.disp[i] and slack > 0.0):
                continue
            if self.lsq or np.isfinite(self.floor0[i]):
                cn[j] += slack + 1e-12 * self.scale[j]
            elif self.c0[j] > self.c[j]:
                cn[j] = min(self.c[j] + slack + 1e-12 * self.scale[j], self.c0[j])
        if np.array_equal(cn, self.c):
            return
        sn, rn, Dn = self.run.solve(cn, state=self._slack_state(cn))
        if rn is None:
            self.run.solve(self.c)  # the Problem's warm state back at c
            return
        self._set(cn, sn, rn, Dn)

    def _slack_state(self, cn):
        """The guess vector (base frame [n(0), m(0), tension, slack]) of the equilibrium at
        controls cn that differ from the current ones only in slack (or just slack)
        displacement controls: the same equilibrium (a slack tendon moves nothing), those
        tendons' slack changed by the length paid out, c - cn."""
        nt = len(self.sol.tension)
        state = np.array(self.sol.raw["base_state"], dtype=float)
        for j, i in enumerate(self.run.idx):
            if cn[j] != self.c[j]:
                state[6 + i] = 0.0
                state[6 + nt + i] = max(self.sol.slack[i] + (self.c[j] - cn[j]), 0.0)
        return state

    def _wanted_sides(self):
        """The side of its switch whose derivatives each tendon at it is to get: the taut
        one for the displacement controls of least squares, those the least change holds
        taut (their steps keep them there) and those it would pull toward their scene
        value (pulling acts through the taut side); the side it is on for the others."""
        side = np.zeros(len(self.disp))
        pull = (self.c0 > self.c) & (not self.lsq)
        want = self.disp_idx & (self.lsq | np.isfinite(self.floor0[self.idx]) | pull)
        side[self.idx[want]] = 1.0
        side[self.slack_side] = -1.0  # (least squares: see lm)
        return side

    A = property(lambda self: self._linearisation()[0])
    T = property(lambda self: self._linearisation()[1])
    side = property(lambda self: self._linearisation()[2])

    def floors(self):
        """Lower bounds on the signed tensions psi (nt,) [N]: the scene's taut tendons'
        (min_tension), and 0 for the displacement controls taut or at the taut side of
        their switch now (the least change puts one that would rather be slack exactly at
        its switch, where it stops costing)."""
        f = self.floor0.copy()
        held = self.sol.tension[self.idx] > 0.0
        if not np.all(held[self.disp_idx]):  # (the side needs the linearisation)
            held |= self.side[self.idx] > 0
        i = self.idx[self.disp_idx & held]
        f[i] = np.maximum(f[i], 0.0)
        return f

    def _merit(self, c, r, tau, floor):
        viol = np.maximum(floor - tau, 0.0)[np.isfinite(floor)].sum() / self.tau_scale
        return 0.5 * np.sum(((c - self.c0) / self.scale) ** 2) + self.nu * (np.abs(r).sum() + viol)

    def _grad(self, c, A, T, rows):
        """The Lagrangian's gradient (scaled) with the last multipliers."""
        g = (c - self.c0) / self.scale - A.T @ self.lam
        if len(rows):
            g = g - (T[rows] / self.tau_scale).T @ self.mus[rows]
        return g

    def _box(self, n, delta):
        """Rows (G, h) of the trust region |u_j| <= delta, of tension controls >= 0 and,
        for a slack displacement control linearised on its slack side, of pulls no
        longer than its slack (beyond it the tendon acts, which that side cannot see)."""
        if self._rows is None:  # the rows but the region's size: fixed at a state
            sl = self.sol.slack[self.idx]
            slack = np.flatnonzero(self.disp_idx & (sl > 0.0) & (self.side[self.idx] <= 0))
            h = [-(self.c / self.scale)[self.bound], -sl[slack] / self.scale[slack]]
            self._rows = np.concatenate([self.G0, -self.eye[slack]]), np.concatenate(h)
        G, h = self._rows
        return G, np.concatenate([np.full(2 * n, -delta), h])

    def _accepted(self, cn, sn, rn, Dn, grad_rows=None):
        """Move to the solved state at cn (with the BFGS update of the least change)."""
        if grad_rows is not None:
            g_old = self._grad(self.c, self.A, self.T, grad_rows)
            s = (cn - self.c) / self.scale
            taut = self.sol.tension > 0.0
            self._set(cn, sn, rn, Dn)
            if np.array_equal(taut, sn.tension > 0.0):
                self.H = _bfgs(self.H, s, self._grad(cn, self.A, self.T, grad_rows) - g_old)
            else:
                # a tendon crossed its taut/slack switch: the Lagrangian's gradient jumps
                # there, so the change of gradient measures no curvature; start afresh
                self.H = np.eye(len(cn))
        else:
            self._set(cn, sn, rn, Dn)
        self.rejected = 0

    def _refused(self, u):
        """A step the solved states do not bear out: the trust region shrinks below it."""
        self.delta = np.abs(u).max() / 4.0
        self.rejected += 1
        return "stuck" if self.rejected >= _MAX_REJECTED else "rejected"

    def _normal_step(self, n, G, h):
        """The step toward the target within 0.8 of the trust region and the constraints
        (G u >= h besides the region; least squares on the linearised residual): the part
        of the target a step of this size can reach."""
        A, r = self.A, self.r
        H = A.T @ A
        H = H + 1e-12 * (np.trace(H) / n + 1e-300) * np.eye(n)
        Gb, hb = self._box(n, 0.8 * self.delta)
        z = np.zeros(n)
        GG, hh = np.concatenate([G, Gb]), np.concatenate([h, hb])
        return solve_qp(H, A.T @ r, np.zeros((0, n)), GG, hh, z).u

    def sqp(self):
        """One trust-region step of the least change (a normal step toward the target,
        then the least change keeping that progress; Byrd and Omojokun's composite step):
        'done', 'moved', 'rejected', 'stuck' or 'unreachable'."""
        self._linearisation()  # first: it may move the state onto a taut side
        n, c, r, sol = len(self.c), self.c, self.r, self.sol
        floor = self.floors()
        rows = np.flatnonzero(np.isfinite(floor))
        Gf = self.T[rows] / self.tau_scale
        psi = self.run.psi(sol)
        hf = (floor[rows] - psi[rows]) / self.tau_scale
        v = self._normal_step(n, Gf, hf)
        rnorm = np.abs(r).max()
        if rnorm > self.tol and not (r @ r - (r + self.A @ v) @ (r + self.A @ v) > 1e-28 * (r @ r)):
            return "unreachable"  # no step within the tensions brings the target nearer
        Gb, hb = self._box(n, self.delta)
        u0 = (c - self.c0) / self.scale
        GG, hh = np.concatenate([Gf, Gb]), np.concatenate([hf, hb])
        qp = solve_qp(self.H, u0, self.A, GG, hh, v)
        u = qp.u
        self.lam = qp.lam
        self.mus = np.zeros(len(floor))
        self.mus[rows] = qp.mu[: len(rows)]
        lam_mu = np.concatenate([np.ravel(self.lam), self.mus])
        self.nu = max(self.nu, 2.0 * np.abs(lam_mu).max(initial=0.0) + 1e-3)
        viol = np.maximum(floor - psi, 0.0)[rows].max(initial=0.0) / self.tau_scale
        # stay: the step and the stationarity residual H u of the linearised problem's
        # optimality conditions both below _KKT_TOL (scaled units), a KKT point
        small = max(np.abs(u).max(), np.abs(self.H @ u).max()) <= _KKT_TOL
        if rnorm <= self.tol and viol <= 1e-9 and small:
            self.optimal = True
            return "done"  # the linearised problem says stay: a KKT point
        phi = self._merit(c, r, psi, floor)
        cn = c + u * self.scale
        sn, rn, Dn = self.run.solve(cn)
        if rn is not None and not self._merit(cn, rn, self.run.psi(sn), floor) < phi:
            # a second-order correction: the new target residual removed by the
            # least-norm step of the same linearisation (the target's curvature would
            # otherwise make the merit refuse steps near the solution)
            d = np.linalg.lstsq(self.A, -rn, rcond=1e-12)[0]
            s2, r2, D2 = self.run.solve(cn + d * self.scale)
            if (
                r2 is not None
                and self._merit(cn + d * self.scale, r2, self.run.psi(s2), floor) < phi
            ):
                u, cn, sn, rn, Dn = u + d, cn + d * self.scale, s2, r2, D2
            else:
                rn = None
        if rn is None:
            return self._refused(u)
        if np.abs(u).max() >= 0.9 * self.delta and np.abs(rn).max() <= rnorm:
            self.delta *= 2.0
        keep = rows[self.mus[rows] > 0.0]  # the tension floors the step holds
        cn, sn, rn, Dn = self._chord(cn, sn, rn, Dn, rnorm, self.T[keep] / self.tau_scale)
        self._accepted(cn, sn, rn, Dn, rows)
        return "moved"

    def _chord(self, cn, sn, rn, Dn, rnorm, Tkeep):
        """An accepted step whose target residual fell fast (to 1e-2 of the last one or
        less, Newton's quadratic regime) but not below tol, corrected by the same
        linearisation: the least-norm change that removes that residual and keeps the
        tensions ``Tkeep`` (rows, scaled) where the step put them, solved.  Its residual is
        the step's times the relative change of the linearisation over the step, so one
        correction usually meets tol where another iteration (a linearisation) would be
        needed.  The corrected state where it reduces the residual, else the step's."""
        rmax = np.abs(rn).max()
        if not (self.tol < rmax <= 1e-2 * rnorm):
            return cn, sn, rn, Dn
        M = np.vstack([self.A, Tkeep])
        rhs = np.concatenate([-rn, np.zeros(len(Tkeep))])
        d = np.linalg.lstsq(M, rhs, rcond=1e-12)[0]
        c2 = cn + d * self.scale
        s2, r2, D2 = self.run.solve(c2)
        if r2 is None or not np.abs(r2).max() < rmax:
            self.run.solve(cn)  # the Problem's warm state back at cn
            return cn, sn, rn, Dn
        return c2, s2, r2, D2

    def lm(self):
        """One trust-region step on |r|^2: 'done', 'moved', 'rejected' or 'stuck'."""
        if np.abs(self.r).max() <= self.tol:
            return "done"
        A, side = self.A, self.side  # first: the linearisation may take up slack
        r, n = self.r, len(self.c)
        H = A.T @ A
        H = H + 1e-12 * (np.trace(H) / n + 1e-300) * np.eye(n)
        G, h = self._box(n, self.delta)
        # a displacement control at its switch (taut side, no tension to speak of): its
        # linearisation holds for pulling only (paid out, it goes slack and moves nothing)
        held = [
            j
            for j, i in enumerate(self.run.idx)
            if self.disp[i] and side[i] > 0 and self.sol.tension[i] <= 1e-9 * self.tau_scale
        ]
        if held:
            G, h = np.concatenate([G, np.eye(n)[held]]), np.concatenate([h, np.zeros(len(held))])
        u = solve_qp(H, A.T @ r, np.zeros((0, n)), G, h, np.zeros(n)).u
        # a held tendon that the step would slacken (its predicted tension falls, through
        # the other controls) is on its slack side there, whose derivatives are not the
        # taut side's: the step again from the linearisation with that side (once per
        # state; a fall below 1e-6 of the tension scale is round-off of a held tendon)
        fall = -1e-6 * self.tau_scale
        flip = [self.run.idx[j] for j in held if self.T[self.run.idx[j]] @ u < fall]
        if flip and not self.slack_side:
            self.slack_side = flip
            self._lin = self._rows = None
            return self.lm()
        pred = r @ r - (r + A @ u) @ (r + A @ u)
        if not pred > 1e-28 * (r @ r) or np.abs(u).max() <= 1e-13:
            return "stuck"  # no descent left: a (bounded) least-squares point
        cn = self.c + u * self.scale
        sn, rn, Dn = self.run.solve(cn)
        rho = (r @ r - rn @ rn) / pred if rn is not None else -1.0
        if rho <= 1e-4:
            return self._refused(u)
        if rho > 0.75 and np.abs(u).max() >= 0.9 * self.delta:
            self.delta *= 2.0
        elif rho < 0.25:
            self.delta = np.abs(u).max() / 2.0
        self._accepted(cn, sn, rn, Dn)
        return "moved"

    def _release(self):
        """Minimum change: a displacement control held at its taut/slack switch above its
        scene value is paid out to that value when the tendon stays slack there (a slack
        tendon moves nothing, so the target stays met and the change only shrinks)."""
        disp, idx = self.disp, self.run.idx
        cn = self.c.copy()
        for j, i in enumerate(idx):
            at_floor = self.mus is not None and self.mus[i] > 0.0
            at_switch = self.side[i] > 0 or self.sol.tension[i] <= 1e-9 * self.tau_scale
            if disp[i] and at_switch and (at_floor or self.sol.tension[i] <= 0.0):
                if cn[j] > self.c0[j]:
                    cn[j] = self.c0[j]
        if np.array_equal(cn, self.c):
            return
        sn, rn, Dn = self.run.solve(cn, state=self._slack_state(cn))
        if (
            rn is not None
            and np.abs(rn).max() <= self.tol
            and all(sn.tension[idx[j]] == 0.0 for j in range(len(cn)) if cn[j] != self.c[j])
        ):
            self._set(cn, sn, rn, Dn)
        else:  # back to the verified point (and the Problem's warm state at it)
            sn, rn, Dn = self.run.solve(self.c)
            self._set(self.c, sn, rn, Dn)

    def iterate(self, max_iter, report):
        """Steps until done, stuck or out of iterations: the arguments of
        ``actuation._finish`` but ``strict``, and the reason of a failure last."""
        sqp = report["kind"] == "minimum-change"
        self.lsq = not sqp
        why = ""
        it = 0
        out = "moved"
        while it < max_iter:
            it += 1
            out = self.sqp() if sqp else self.lm()
            if out == "unreachable":
                why = "the target lies beyond what the tensions allow"
                break
            if out in ("done", "stuck"):
                break
        if sqp and out == "done":
            self._release()
        report["optimal"] = self.optimal or not sqp
        floor = self.floors()
        active = tuple(
            int(i)
            for i in np.flatnonzero(np.isfinite(floor))
            if self.mus is not None and self.mus[i] > 0.0
        )
        converged = out in ("done", "stuck", "unreachable")
        constrained = tuple(int(i) for i in np.flatnonzero(np.isfinite(floor)))
        return (
            self.sol,
            self.c,
            self.r,
            report,
            constrained,
            active,
            self.lam,
            self.mus,
            it,
            converged,
            self.tol,
            why,
        )
