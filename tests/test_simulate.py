"""tr.simulate: the dynamics in time against what is known independently.

Work is bounded by counting: every run has a fixed number of steps, each step at most
``max_iter`` Newton iterations (asserted through ``nit``), no wall-clock timing.
"""

import math

import numpy as np
import pytest

import tendonrod as tr
from tendonrod.dynamics import simulate, simulation_options

ROD = tr.Rod(0.2, 2e-3, 207e9, 79.6e9, density=7800.0)
FREE = tr.Scene(tr.Robot(ROD, []))


def _released(force, steps=40):
    """The static state under a tip force, the scene without it."""
    held = tr.Scene(tr.Robot(ROD, []), loads=[tr.PointLoad(0.2, force)])
    return tr.solve(held, options=simulation_options(steps))


def _period(t, x):
    """Mean period from the zero crossings of x (linear interpolation)."""
    i = np.where(np.sign(x[:-1]) != np.sign(x[1:]))[0]
    tc = t[i] - x[i] * (t[i + 1] - t[i]) / (x[i + 1] - x[i])
    return 2.0 * float(np.mean(np.diff(tc)))


@pytest.fixture(scope="module")
def f1():
    return float(tr.modes(FREE, n=1).frequencies[0])


@pytest.fixture(scope="module")
def ring(f1):
    """Three periods of the released cantilever, omega dt = 0.04 (trapezoidal rule)."""
    dt = 0.04 / (2 * math.pi * f1)
    return dt, simulate(
        FREE, 3.0 / f1, dt, initial=_released((1e-4, 0.0, 0.0)), options={"alpha": -0.5}
    )


def test_period_is_first_mode(f1, ring):
    dt, tj = ring
    assert tj.success, tj.message
    # bounded work: 471 steps, at most 8 iterations each (max_iter)
    assert len(tj.t) == 472 and tj.nit <= 8 * 471
    T = _period(tj.t, tj.tip_position[:, 0])
    # the 1e-3 against 1/f1 of tr.modes (the trapezoidal rule's own period error
    # at omega dt = 0.04 is (omega dt)^2 / 12 = 1.3e-4)
    assert abs(T * f1 - 1.0) < 1e-3
    # with the trapezoidal rule's exact dispersion of a linear oscillator,
    # omega_h = (2 / dt) atan(omega dt / 2), what is left (5.1e-4 measured, the same at
    # omega dt = 0.08: not the time step's) is the zero crossings' shift by the higher
    # modes the release excites, or the grid's: bounded here, not yet explained
    w = 2 * math.pi * f1
    wd = 2.0 / dt * math.atan(w * dt / 2.0)
    assert abs(T * wd / (2 * math.pi) - 1.0) < 8e-4


def test_euler_bernoulli_period(ring):
    """The same period from Euler-Bernoulli's beta L = 1.875104, to the shear and rotary
    inertia correction of a slender rod: (d / L)^2 = 1e-4 relative, well inside 1e-3."""
    dt, tj = ring
    EI = ROD.bending_stiffness
    w = 1.875104**2 * math.sqrt(EI / (ROD.mass_per_length * 0.2**4))
    assert abs(_period(tj.t, tj.tip_position[:, 0]) * w / (2 * math.pi) - 1.0) < 1e-3


def test_undamped_energy(ring):
    """Undamped: kinetic + elastic energy is kept by the trapezoidal rule up to its
    documented oscillation (docs/guide/dynamics.md: below 1 % of the energy at
    omega dt <= 0.08, shrinking with dt), and does not drift: the mean over the last
    period equals the mean over the first to 1e-3."""
    dt, tj = ring
    E = tj.energy[:, 0] + tj.energy[:, 1]
    E0 = E[0]
    assert np.ptp(E) / E0 < 1e-2
    n = len(E) // 3
    assert abs(E[-n:].mean() - E[:n].mean()) / E0 < 1e-3
    assert np.all(tj.energy[:, 3] == 0.0)  # nothing dissipates without damping


def test_damped_decays_to_static():
    """With damping, the motion decays to the static solve of the final actuation: a
    tendon robot's displacement ramp; the end state against tr.solve on the same grid to
    1e-7 L (the static solver's tolerance scaled, the decay left after 40 periods)."""
    rod = tr.Rod(0.2, 2e-3, 207e9, 79.6e9, density=7800.0, damping=2e-3)
    robot = tr.Robot(rod, [tr.Tendon(offset=0.004, angle=0.0, EA=2e4)])
    q1 = 5e-4
    scene0 = tr.Scene(robot, displacement=[0.0])
    scene1 = tr.Scene(robot, displacement=[q1])

    def act(t):
        return [q1 * min(t / 0.02, 1.0)]

    tj = simulate(scene0, 0.5, 1e-3, actuation=act)  # BDF2, the default
    assert tj.success, tj.message
    ref = tr.solve(scene1, options=simulation_options())
    assert np.linalg.norm(tj.tip_position[-1] - ref.tip_position) < 1e-7 * 0.2
    assert abs(tj.tension[-1, 0] - ref.tension[0]) < 1e-6 * ref.tension[0]
    assert tj.energy[-1, 3] > 0.0


def test_slow_ramp_is_quasi_static():
    """A ramp slow against the first period (1 s against 28 ms) follows the static
    solutions along it: the tip within 1e-3 of the tip's travel (the inertial lag
    rho A a L / k ~ (T1 / T_ramp)^2)."""
    robot = tr.Robot(ROD, [tr.Tendon(offset=0.004, angle=0.0, EA=math.inf)])
    tau1 = 2.0

    def act(t):
        return [tau1 * t]

    tj = simulate(tr.Scene(robot, tension=[0.0]), 1.0, 0.01, actuation=act, options={"alpha": 0.0})
    assert tj.success, tj.message
    travel = np.linalg.norm(tj.tip_position[-1] - tj.tip_position[0])
    for i in (50, 100):
        ref = tr.solve(tr.Scene(robot, tension=[tau1 * tj.t[i]]), options=simulation_options())
        assert np.linalg.norm(tj.tip_position[i] - ref.tip_position) < 1e-3 * travel


def test_refusals_and_save(tmp_path, ring):
    kir = tr.Rod(0.2, 2e-3, 207e9, 79.6e9, density=7800.0, kirchhoff=True)
    with pytest.raises(ValueError, match="Kirchhoff"):
        simulate(tr.Scene(tr.Robot(kir, [])), 0.01, 1e-3)
    with pytest.raises(ValueError, match="mass"):
        simulate(tr.Scene(tr.Robot(tr.Rod(0.2, 2e-3, 207e9, 79.6e9), [])), 0.01, 1e-3)
    with pytest.raises(ValueError, match="dt"):
        simulate(FREE, 0.01, -1.0)
    with pytest.raises(ValueError, match="alpha"):
        simulate(FREE, 0.01, 1e-3, options={"alpha": 0.5})
    _, tj = ring
    tj.save(tmp_path / "t.npz")
    back = tr.Trajectory.load(tmp_path / "t.npz")
    assert np.array_equal(back.tip_position, tj.tip_position) and back.success


def test_time_error_estimate(f1):
    """The dt-halving estimate against the error itself (a run at dt/8 as the reference,
    BDF2): their maxima over one period within a factor 2 (second order: the estimate's
    own error is the dt/2 run's, a quarter of the dt run's, plus higher order terms; a
    single time is not compared, where the error passes through zero)."""
    dt = 0.1 / (2 * math.pi * f1)
    start = _released((1e-4, 0.0, 0.0))
    tj = simulate(FREE, 63 * dt, dt, initial=start, options={"estimate": True})
    ref = simulate(FREE, 63 * dt, dt / 8, initial=start)
    err = np.linalg.norm(tj.tip_position - ref.tip_position[::8], axis=1)
    assert tj.time_error is not None and 0.5 < tj.time_error.max() / err.max() < 2.0


def test_failed_step_is_reported():
    """A retraction of a quarter of L in one step has no converging Newton step: the run
    stops there, says when and why, and keeps the trajectory before it."""
    robot = tr.Robot(ROD, [tr.Tendon(offset=0.004, angle=0.0, EA=2e4)])
    scene = tr.Scene(robot, displacement=[0.0])
    with pytest.warns(tr.ConvergenceWarning, match=r"step 5 \(t = 0.005 s\) failed"):
        tj = simulate(scene, 0.01, 1e-3, actuation=lambda t: [0.0 if t < 0.005 else 0.05])
    assert not tj.success and tj.status < 0
    assert len(tj.t) == 5 and tj.t[-1] == pytest.approx(0.004)
    # its growth is too small for more segments to help: not redone (tr_dyn_retry_segments)
    assert tj.segments == 1 and "tried" not in tj.message


def test_damped_energy_balance(f1):
    """Kelvin-Voigt damping: kinetic + strain + dissipated energy stays the initial strain
    energy (no external work after the release) to 2e-3 of it at omega dt = 0.04 (1.3e-3
    measured, 4e-4 at half the dt: the scheme's error, not a leak); and the mechanical
    energy decays as the first mode's exp(-eta omega1^2 t) (its damping ratio eta omega / 2)
    to 5 % (the higher modes of the released shape, ~3 % of its energy, decay faster)."""
    eta = 1e-4
    rod = tr.Rod(0.2, 2e-3, 207e9, 79.6e9, density=7800.0, damping=eta)
    held = tr.Scene(tr.Robot(rod, []), loads=[tr.PointLoad(0.2, (1e-4, 0.0, 0.0))])
    start = tr.solve(held, options=simulation_options())
    w = 2 * math.pi * f1
    tj = simulate(
        tr.Scene(tr.Robot(rod, [])), 3.0 / f1, 0.04 / w, initial=start, options={"alpha": -0.5}
    )
    assert tj.success, tj.message
    E = tj.energy
    total = E[:, 0] + E[:, 1] + E[:, 3]
    assert np.abs(total - total[0]).max() < 2e-3 * E[0, 1]
    mech = (E[-1, 0] + E[-1, 1]) / E[0, 1]
    assert abs(mech / math.exp(-eta * w * w * 3.0 / f1) - 1.0) < 0.05


def test_resume_and_backbone():
    """A run resumed from another's last step continues it: its times and tip equal those
    of one run over both halves (to 1e-12 m: the resumed first step starts from a fresh
    difference Jacobian instead of the carried one: the same state to the Newton
    tolerance).  The backbone's last node is the tip."""
    rod = tr.Rod(0.2, 2e-3, 207e9, 79.6e9, density=7800.0, damping=1e-4)
    robot = tr.Robot(rod, [tr.Tendon(offset=0.004, angle=0.0, EA=2e4)])
    scene = tr.Scene(robot, displacement=[0.0])

    def act(t):
        return [5e-4 * min(t / 0.01, 1.0)]

    full = simulate(scene, 0.04, 2e-4, actuation=act, options={"backbone": True})
    first = simulate(scene, 0.02, 2e-4, actuation=act)
    second = simulate(scene, 0.02, 2e-4, actuation=act, initial=first)
    assert full.success and second.success
    assert np.allclose(second.t, full.t[100:], rtol=0, atol=1e-15)
    assert np.abs(second.tip_position - full.tip_position[100:]).max() < 1e-12
    # the dissipated energy: to the Newton tolerance's share (1e-10 scaled), 5e-16 J measured
    assert np.abs(second.energy[:, 3] - full.energy[100:, 3]).max() < 1e-9 * full.energy[-1, 3]
    # the motor's work goes on from the first run's (the same tolerance's share)
    assert np.abs(second.energy[:, 5] - full.energy[100:, 5]).max() < 1e-9 * full.energy[-1, 5]
    assert full.backbone.shape == (201, 41, 3) and full.s[-1] == 0.2
    assert np.array_equal(full.backbone[:, -1], full.tip_position)
    with pytest.raises(ValueError, match="dt"):
        simulate(scene, 0.02, 1e-4, actuation=act, initial=first)


def test_cancel_stops_the_run():
    """The core polls its caller during a run (tr_poll): a cancelled token stops it, as for
    the statics (KeyboardInterrupt from the glue)."""
    from tendonrod import _core
    from tendonrod.compiled import _compile

    sol = tr.solve(FREE, options=simulation_options())
    rI = 7800.0 * math.pi * 2e-3**4 / 64.0
    token = _core.Cancel()
    token.set()
    with pytest.raises(KeyboardInterrupt):
        _core.simulate(
            _compile(FREE, sol.options),
            sol.unknowns,
            np.zeros((100001, 0)),  # a run far longer than the poll interval (2 ms)
            None,
            1e-4,
            rho_a=ROD.mass_per_length,
            rho_j=np.array([rI, rI, 2 * rI]),
            cancel=token,
        )


@pytest.fixture(scope="module")
def swing():
    """A released cantilever with its backbone recorded: 60 steps (61 rows) of 41 nodes."""
    start = _released((1e-3, 0.0, 0.0))
    tj = simulate(FREE, 60 * 2e-4, 2e-4, initial=start, options={"backbone": True})
    assert tj.success and tj.backbone is not None and tj.backbone.shape == (61, 41, 3)
    return tj


def test_load_reads_a_trajectory(tmp_path, swing):
    """tr.load tells a trajectory's file from a solution's by its format marker: every
    array comes back bit for bit, the scalars equal; a foreign .npz is refused by name."""
    swing.save(tmp_path / "t.npz")
    back = tr.load(tmp_path / "t.npz")
    assert isinstance(back, tr.Trajectory)
    for k in (
        "t",
        "tip_position",
        "tip_rotation",
        "tension",
        "slack",
        "energy",
        "residual",
        "iterations",
        "backbone",
        "s",
    ):
        a, b = getattr(swing, k), getattr(back, k)
        assert a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes(), k
    assert back.time_error is None and back.final is None
    assert (back.success, back.status, back.message, back.nit, back.nfev) == (
        swing.success,
        swing.status,
        swing.message,
        swing.nit,
        swing.nfev,
    )
    sol = tr.solve(FREE, options=simulation_options())
    sol.save(tmp_path / "s.npz")
    assert isinstance(tr.load(tmp_path / "s.npz"), tr.Solution)
    np.savez(tmp_path / "foreign.npz", format=np.array("something else"), x=np.zeros(3))
    with pytest.raises(ValueError, match="foreign.npz.*not a file written by tendonrod"):
        tr.load(tmp_path / "foreign.npz")
    # a trajectory's marker with its arrays missing: refused by name, not a KeyError
    np.savez(tmp_path / "cut.npz", format=np.array("tendonrod.Trajectory 1"))
    with pytest.raises(ValueError, match="cut.npz.*not a valid Trajectory file"):
        tr.load(tmp_path / "cut.npz")


def test_view_animates_the_backbone(swing):
    """tr.plot.view of a trajectory (no browser): one frame per drawn row, at most
    max_frames of them (first and last kept), each the tube around that row's recorded
    centre line at the rod's radius and the tip marker at that row's tip; a trajectory
    without backbone states, or a scene of another rod, is refused."""
    pytest.importorskip("plotly")
    sides = 12
    fig = tr.plot.view(swing, FREE, sides=sides, max_frames=25)
    rows = fig.layout.meta["tendonrod_rows"]
    assert len(fig.frames) == len(rows) == 25 and rows[0] == 0 and rows[-1] == 60
    assert [s.label for s in fig.layout.sliders[0].steps] == [
        f"t = {swing.t[i]:.6g} s" for i in rows
    ]
    nb = swing.backbone.shape[1]
    for frame, i in zip(fig.frames, rows):
        tube, tip = frame.data
        V = np.stack([tube.x, tube.y, tube.z], -1)
        assert V.shape == (nb * sides + 2, 3)  # the rings and the caps' two centres
        P = swing.backbone[i]
        # ring k's vertices at the rod's radius from node k (the rings are built at exactly
        # the radius: round-off only)
        rad = np.linalg.norm(V[: nb * sides].reshape(nb, sides, 3) - P[:, None, :], axis=-1)
        assert np.abs(rad - 1e-3).max() < 1e-12
        assert np.array_equal(np.array([tip.x[0], tip.y[0], tip.z[0]]), swing.tip_position[i])
    names = [t.name for t in fig.data]
    assert names[:3] == ["backbone (d = 2 mm)", "tip", "tip path"] and "world frame" in names
    assert len(fig.data[2].x) == len(swing.t)  # the tip's path: every row
    few = tr.plot.view(swing, max_frames=200)  # fewer rows than max_frames: every row
    assert len(few.frames) == len(swing.t) and few.data[0].name.startswith("backbone (its")
    plain = simulate(FREE, 2e-3, 1e-3)
    with pytest.raises(ValueError, match="no backbone states.*backbone"):
        tr.plot.view(plain)
    short = tr.Scene(tr.Robot(tr.Rod(0.1, 2e-3, 207e9, 79.6e9, density=7800.0), []))
    with pytest.raises(ValueError, match="0.1 m long"):
        tr.plot.view(swing, short)


def test_short_steps_take_multiple_shooting():
    """Short steps make the inertia rho A c0^2 a stiff foundation for the bending: each
    step's single-shooting problem grows like exp(19.7) here (omega1 dt = 0.0068) and its
    first step fails, as every run at such a dt did before multiple shooting.  The default
    takes the segments from that growth (3, tr_dyn_segments) and converges every step
    within max_iter iterations; the trapezoidal rule then keeps the undamped energy to
    1e-3 of it (1.3e-4 measured: the release's geometric nonlinearity and the Newton
    tolerance; a linear motion's energy it keeps exactly)."""
    dt = 3e-5
    start = _released((1e-4, 0.0, 0.0))
    with pytest.warns(tr.ConvergenceWarning, match=r"step 1 \(t = 3e-05 s\) failed"):
        one = simulate(FREE, 40 * dt, dt, initial=start, options={"segments": 1, "alpha": -0.5})
    assert not one.success and len(one.t) == 1
    tj = simulate(FREE, 40 * dt, dt, initial=start, options={"alpha": -0.5})
    assert tj.success, tj.message
    assert "(3 shooting segments)" in tj.message
    # bounded work: 40 steps, at most max_iter = 8 Newton iterations each
    assert len(tj.t) == 41 and tj.nit <= 8 * 40
    E = tj.energy[:, 0] + tj.energy[:, 1]
    assert np.ptp(E) / E[0] < 1e-3


def test_extrapolation_in_dt():
    """options['extrapolate']: runs at dt, dt/2, dt/4 Richardson-extrapolated, on a damped
    tendon robot under a displacement ramp (its corners as in Till's scene), against the
    same at dt/8 (its own estimate 7e-7 of the travel).  The extrapolated tip is 10x closer
    than the plain dt/4 run (4.1e-5 against 4.1e-4 of the travel measured; asserted 5x),
    and its error estimate bounds the error from above within a factor 4 (2.65 measured:
    the estimate takes the extrapolation's error as falling by 4 per halving, what corners
    of the actuation leave in Till's scene; here it falls faster)."""
    rod = tr.Rod(0.2, 2e-3, 207e9, 79.6e9, density=7800.0, damping=2e-3)
    robot = tr.Robot(rod, [tr.Tendon(offset=0.004, angle=0.0, EA=2e4)])
    scene = tr.Scene(robot, displacement=[0.0])

    def act(t):
        return [5e-4 * min(t / 0.02, 1.0)]

    ex = simulate(scene, 0.06, 1e-3, actuation=act, options={"extrapolate": True})
    ref = simulate(scene, 0.06, 1.25e-4, actuation=act, options={"extrapolate": True})
    quarter = simulate(scene, 0.06, 2.5e-4, actuation=act)
    assert ex.success and ref.success and ex.final is None
    # bounded work: 60 + 120 + 240 steps of at most 8 iterations each
    assert len(ex.t) == 61 and ex.nit <= 8 * 420
    err = np.linalg.norm(ex.tip_position - ref.tip_position[::8], axis=1).max()
    plain = np.linalg.norm(quarter.tip_position[::4] - ref.tip_position[::8], axis=1).max()
    assert err < plain / 5.0
    assert err <= ex.time_error.max() < 4.0 * err
    R = ex.tip_rotation
    assert np.abs(R @ R.transpose(0, 2, 1) - np.eye(3)).max() < 1e-12
    with pytest.raises(ValueError, match="extrapolate"):
        simulate(scene, 0.01, 1e-3, options={"extrapolate": True, "estimate": True})


def test_energy_balance_with_the_motor():
    """A displacement ramp of a tendon robot under gravity, damped: kinetic + rod strain +
    gravity's potential + dissipated + the tendon's strain energy - the motor's work stays
    its initial value to the scheme's accuracy: at dt = 0.5 ms within 1e-3 of the motor's
    work (4.7e-4 measured, trapezoidal rule), and second order: a quarter of it, within
    20 % (the ratio 4.0 measured), at dt = 0.25 ms."""
    rod = tr.Rod(0.2, 2e-3, 207e9, 79.6e9, density=7800.0, damping=2e-3)
    robot = tr.Robot(rod, [tr.Tendon(offset=0.004, angle=0.0, EA=2e4)])
    scene = tr.Scene(robot, displacement=[0.0], gravity=(-9.81, 0.0, 0.0))

    def act(t):
        return [5e-4 * min(t / 0.02, 1.0)]

    gaps = []
    for dt in (5e-4, 2.5e-4):
        tj = simulate(scene, 0.06, dt, actuation=act, options={"alpha": -0.5})
        assert tj.success, tj.message
        E = tj.energy
        assert E.shape == (len(tj.t), 6) and E[0, 5] == 0.0 and E[-1, 5] > 0.0
        total = E[:, 0] + E[:, 1] + E[:, 2] + E[:, 3] + E[:, 4] - E[:, 5]
        gaps.append(np.abs(total - total[0]).max() / E[-1, 5])
    assert gaps[0] < 1e-3
    assert 0.8 * 4.0 < gaps[0] / gaps[1] < 1.2 * 4.0


SOFT = tr.Rod(1.0, 0.01, 5e8, 5e8 / 3, density=1000.0)


def test_initial_released_into_gravity():
    """``initial`` is the start's pose, under its own scene's loads: a straight rod (solved
    without gravity) released into gravity along -x starts straight and falls along -x."""
    start = tr.solve(tr.Scene(tr.Robot(SOFT, [])), options=simulation_options())
    run = tr.Scene(tr.Robot(SOFT, []), gravity=(-9.81, 0, 0))
    traj = simulate(run, 0.02, 0.005, initial=start)
    assert traj.success, traj.message
    # the straight pose exactly: only round-off in the integration of the start's unknowns
    assert np.abs(traj.tip_position[0] - (0.0, 0.0, 1.0)).max() <= 1e-12 * SOFT.length
    # it falls: the tip moves along -x at once, farther each step, nothing along y
    x = traj.tip_position[:, 0]
    assert x[1] < 0 and np.all(np.diff(x) < 0)
    assert np.abs(traj.tip_position[:, 1]).max() <= 1e-12 * SOFT.length


def test_initial_load_removed_keeps_its_pose():
    """A load removed at the start: the run starts at the loaded pose (an interior load,
    whose position the run's scene does not have), then springs back."""
    held = tr.Scene(tr.Robot(ROD, []), loads=[tr.PointLoad(0.13, (2e-2, 0, 0))])
    start = tr.solve(held, options=simulation_options())
    traj = simulate(FREE, 6e-3, 2e-4, initial=start)
    assert traj.success, traj.message
    # round-off of the same integration of the same unknowns under the same loads
    assert np.abs(traj.tip_position[0] - start.tip_position).max() <= 1e-12 * ROD.length
    # released: a quarter period (1 / (4 f1) = 6.3 ms) later the tip is near the line
    # (measured: a quarter of its start)
    assert traj.tip_position[-1, 0] < 0.5 * traj.tip_position[0, 0]
    # it starts with the held pose's strain energy and nothing else
    assert traj.energy[0, 0] == 0.0 and traj.energy[0, 1] > 0.0


def test_initial_of_another_structure_is_refused():
    """What the start's values cannot carry over is refused, naming initial."""
    tendon = tr.Tendon(offset=1e-3, angle=0.0)
    robot = tr.Robot(ROD, [tendon])
    start = tr.solve(tr.Scene(robot, tension=[0.5]), options=simulation_options())
    others = (
        tr.Scene(tr.Robot(ROD, [])),  # no tendon
        tr.Scene(
            tr.Robot(ROD, [tr.Tendon(offset=2e-3, angle=0.0)]), tension=[0.5]
        ),  # another offset
        tr.Scene(robot, displacement=[0.0]),  # displacement- instead of tension-held
        tr.Scene(tr.Robot(SOFT, [tendon]), tension=[0.5]),  # another rod
    )
    for scene in others:
        with pytest.raises(ValueError, match="initial"):
            simulate(scene, 1e-3, 1e-4, initial=start)
    # a tension value differing is honoured: it acts from the first step on
    traj = simulate(tr.Scene(robot, tension=[1.0]), 1e-3, 1e-4, initial=start)
    assert traj.success
    assert np.abs(traj.tip_position[0] - start.tip_position).max() <= 1e-12 * ROD.length
    assert traj.tension[0, 0] == pytest.approx(0.5) and traj.tension[1, 0] == pytest.approx(1.0)


def test_backbone_arc_lengths_on_uneven_breakpoints():
    """Trajectory.s is the true grid: with a point load at 0.35 L the RK4 steps on either
    side differ (10 steps: 4 of 0.0875 m, 7 of 0.65/7 m); the backbone at t = 0 is the
    static solution at those arc lengths."""
    scene = tr.Scene(tr.Robot(SOFT, []), loads=[tr.PointLoad(0.35, (0.5, 0, 0))])
    sol = tr.solve(scene, options=simulation_options(10))
    traj = simulate(scene, 0.01, 0.005, options={"steps": 10, "backbone": True})
    want = np.concatenate([np.linspace(0, 0.35, 5)[:-1], np.linspace(0.35, 1.0, 8)])
    np.testing.assert_allclose(traj.s, want, rtol=0, atol=1e-15)
    # the same unknowns recorded on the same grid: round-off
    np.testing.assert_allclose(traj.backbone[0], sol.at(traj.s).position, rtol=0, atol=1e-12)


def test_initial_potential_under_the_runs_gravity():
    """The start's potential energy is taken under the run's gravity (the one the energy
    balance of the steps holds with), not the start's scene's (none here): rho A g times
    the integral of the height over the start's pose."""
    held = tr.Scene(tr.Robot(ROD, []), loads=[tr.PointLoad(0.2, (0.3, 0, 0))])
    start = tr.solve(held, options=simulation_options())
    traj = simulate(tr.Scene(tr.Robot(ROD, []), gravity=(0, 0, -9.81)), 1e-3, 1e-4, initial=start)
    assert traj.success, traj.message
    assert np.abs(traj.tip_position[0] - start.tip_position).max() <= 1e-12 * ROD.length
    z = start.position[:, 2]
    want = ROD.mass_per_length * 9.81 * float(np.sum(0.5 * (z[1:] + z[:-1]) * np.diff(start.s)))
    # the core's RK4 quadrature against the trapezoid on 101 nodes: z is nearly linear in
    # s (a 2.5 % deflection), both far below 1e-6 of it
    assert traj.energy[0, 2] == pytest.approx(want, rel=1e-6)


# the static starts on the 20-step grid warn of its truncation error (each re-solve too)
@pytest.mark.filterwarnings("ignore:.*truncation error:tendonrod.ConvergenceWarning")
def test_failed_step_is_redone_with_more_segments():
    """A 1 m, 10 mm rod (E = 0.5 GPa) released at once from a tip force of twice its weight
    against gravity (bench/dynamics_elastica.py's sudden release): at dt = 3 ms the step's
    growth exponent is 11.9, below the single-shooting limit of tr_dyn_segments, yet the
    first step's single-shooting Newton fails.  With the segments left to simulate, the run
    is redone with 2 (tr_dyn_retry_segments) and completes, saying so; at 2.5 ms (growth
    13.0) 2 segments fail at step 3 and 4 pass.  A user-fixed count is never changed."""
    rod = tr.Rod(1.0, 0.01, 5e8, 5e8 / 3, density=1000.0)
    weight = 1000.0 * math.pi * 0.005**2 * 9.81
    g = (-9.81, 0.0, 0.0)
    free = tr.Scene(tr.Robot(rod, []), gravity=g)
    held = tr.Scene(tr.Robot(rod, []), gravity=g, loads=[tr.PointLoad(1.0, (2 * weight, 0, 0))])
    start = tr.solve(held, options=simulation_options(20))
    opts = {"steps": 20, "max_iter": 30}
    for dt, seg, tried in ((3e-3, 2, "1 (step 1 failed), 2"), (2.5e-3, 4, "2 (step 3 failed), 4")):
        tj = simulate(free, 10 * dt, dt, initial=start, options=opts)
        assert tj.success, tj.message
        assert tj.segments == seg and f"({seg} shooting segments)" in tj.message
        assert tried in tj.message
        # bounded work: at most three runs of 10 steps, each step at most 2 max_iter
        # lean iterations plus the damped fallback's (measured 141 and 159 in all)
        assert len(tj.t) == 11 and tj.nit <= 3 * 10 * 3 * 30
        # undamped BDF2 only dissipates: kinetic + strain + gravity's potential never rises
        # above the start's (to round-off of the 1e-10 Newton tolerance) and the scheme's
        # damping of the release's fast modes takes under 1 % of the strain energy in 10
        # steps (0.21 % and 0.16 % measured)
        e = tj.energy
        total = e[:, 0] + e[:, 1] + e[:, 2]
        assert np.all(total - total[0] <= 1e-8 * e[0, 1])
        assert total[0] - total.min() < 1e-2 * e[0, 1]
    with pytest.warns(tr.ConvergenceWarning, match=r"step 1 \(t = 0.003 s\) failed"):
        one = simulate(free, 10 * 3e-3, 3e-3, initial=start, options={**opts, "segments": 1})
    assert not one.success and one.segments == 1 and "tried" not in one.message
