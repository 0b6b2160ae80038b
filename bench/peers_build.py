"""Build the peers' own C++ codes and time them on their loaded scenes (../shared/peers.md).

The peers' sources are never part of this repository.  Given ``--peer-src DIR``, a folder
holding two public checkouts laid out as their repositories are,

    DIR/ContinuumRobotExamples   github.com/JohnDTill/ContinuumRobotExamples
    DIR/tdcr-modeling            github.com/SvenLilge/tdcr-modeling

this module writes small drivers of its own into a build folder outside the repository
(``--build-dir``, by default ``build-static`` beside DIR), compiles them with ``g++`` and
the flags in ``CXXFLAGS`` (no ``-march``: the x86-64 baseline), and runs them.  Each driver times N cold solves, each from the peer's own
default guess, in thread CPU time (``CLOCK_THREAD_CPUTIME_ID``) and in wall time
(``CLOCK_MONOTONIC``), one line per solve, then prints the tip of the last solve [m, world
frame].

* Till's displacement-controlled tendon robot (``01_Statics/06_Tendon_Robot_Variants/
  Cpp_3/main.cpp`` with the headers of ``Library/``; Eigen from the system when the
  bundled ``Library/eigen`` is absent) is a single-file example with its scene compiled
  in.  ``till_driver_source`` transforms that file by three checked substitutions (each
  anchor must occur exactly once, or the build fails): the gravity constant becomes a
  variable set from the command line; a world-frame tip force, set from the command line,
  enters the tip's force balance beside the tendons' forces (rotated into the tip's body
  frame, as the backbone's internal force is there); and everything from ``int main`` on
  is replaced by the timing loop, which calls the example's own solver with the example's
  own arguments and initial guess, both copied from its ``main``.
* Rao/Lilge's benchmark (``c++/src/cosseratrodmodel.cpp``, ``c++/include/``) is a
  library: ``RAO_DRIVER`` constructs its ``CosseratRodModel`` (what its
  ``TendonDrivenRobot::forwardKinematics`` calls for ``Model::CosseratRod``) with the
  parameters of its shipped ``main.cpp`` (two 0.2 m segments, E = 54 GPa, backbone radius
  0.7 mm, ten disks per segment, pitch radius 10 mm) and one tension of 2 N on the second
  segment's first tendon, at body (0, 0.010, 0) m over the full length: scene R.

Before any timing, each scene's peer tip is compared with tendonrod's tip for the same
scene: a distance beyond the peer's known accuracy (``TIP_TOL``) means the driver's
scene is wrong, and the scene is reported as failed, with the distance.

    .venv/bin/python bench/peers_build.py --peer-src /work/peers/src [--rounds 5]
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import re
import shutil
import statistics
import subprocess
import sys

import numpy as np

CXX = "g++"
CXXFLAGS = ["-O3", "-DNDEBUG", "-std=c++17"]
TILL_MAIN = os.path.join(
    "ContinuumRobotExamples", "01_Statics", "06_Tendon_Robot_Variants", "Cpp_3", "main.cpp"
)
TILL_LIB = os.path.join("ContinuumRobotExamples", "Library")
RAO_CPP = os.path.join("tdcr-modeling", "c++", "src", "cosseratrodmodel.cpp")
RAO_INC = os.path.join("tdcr-modeling", "c++", "include")
SYSTEM_EIGEN = "/usr/include/eigen3"
PEER_SOLVES = 3  # cold solves per driver run (one run per round)

# solve.py's scene name -> (driver, command-line arguments before the solve count):
# Till: gravity along world +x [m/s^2] and the world-frame tip force [N]; Rao: the
# world-frame tip force [N] and the tension [N]
PEER_SCENES = {
    "Till T0 (gravity +x)": ("till", (9.81, 0.0, 0.0, 0.0)),
    "Till T1 (no load)": ("till", (0.0, 0.0, 0.0, 0.0)),
    "Till T2 (tip -0.2 N x)": ("till", (0.0, -0.2, 0.0, 0.0)),
    "Till T3 (tip 0.2 N y)": ("till", (0.0, 0.0, 0.2, 0.0)),
    "Rao R (tip 0.1 N x)": ("rao", (0.1, 0.0, 0.0, 2.0)),
    "Rao R (tip -0.1 N y)": ("rao", (0.0, -0.1, 0.0, 2.0)),
}
# the peer's tip distance from tendonrod's [m] beyond which its driver's scene is wrong.
# Till: classical RK4 on 100 nodes and a sum-of-squares tolerance of 1e-12 on residuals
# mixing newtons, newton metres and metres (peers.md: 1e-6 - 1e-5 m of tip error; measured
# here 1.4e-7 - 1.8e-6 m on T0-T3), twice the upper end.  Rao: RKF45 with GSL's
# control_y_new(1e-6, 1e-3) restarted at every disk and a stopping test on the unscaled
# residual; measured 1.2e-9 m (f = +x) and 8e-10 m (f = -y) on scene R
# (bench/results/peers_built.md): 1e-6 m, a thousandfold margin.
TIP_TOL = {"till": 2e-5, "rao": 1e-6}


class PeerBuildError(RuntimeError):
    """The peers' sources are missing or did not build."""


# --------------------------------------------------------------------------- drivers
TIMING_HELPERS = r"""
#include <time.h>
#include <cstdlib>
// milliseconds on the given clock
static double clock_ms(clockid_t which){
    timespec t;
    clock_gettime(which, &t);
    return 1e3*t.tv_sec + 1e-6*t.tv_nsec;
}
"""

TILL_MAIN_TEMPLATE = r"""
// Timing loop (replaces the example's main): argv = gravity along world +x [m/s^2],
// tip force fx fy fz [N, world frame], number of cold solves.  One line per solve:
// "solve <thread CPU ms> <wall ms>", then "tip x y z" [m] of the last solve.
int main(int argc, char** argv){
    if(argc != 6){
        fprintf(stderr, "usage: %s gravity_x fx fy fz solves\n", argv[0]);
        return 2;
    }
    g = atof(argv[1])*Vector3d::UnitX();
    f_tip << atof(argv[2]), atof(argv[3]), atof(argv[4]);
    const int solves = atoi(argv[5]);
    for(int k = 0; k < solves; k++){
        double c0 = clock_ms(CLOCK_THREAD_CPUTIME_ID), w0 = clock_ms(CLOCK_MONOTONIC);
        @INIT_GUESS@
        try{
            VectorXd wrench_soln = solveLevenbergMarquardt<shootingFunction>(@SOLVER_ARGS@);
        }catch(int){
            printf("fail\n");
            return 1;
        }
        double c1 = clock_ms(CLOCK_THREAD_CPUTIME_ID), w1 = clock_ms(CLOCK_MONOTONIC);
        printf("solve %.6f %.6f\n", c1 - c0, w1 - w0);
    }
    printf("tip %.15e %.15e %.15e\n", Y(0, Y.cols()-1), Y(1, Y.cols()-1), Y(2, Y.cols()-1));
    return 0;
}
"""

RAO_DRIVER = (
    r"""
#include "cosseratrodmodel.h"
#include <stdio.h>
"""
    + TIMING_HELPERS
    + r"""
// argv = tip force fx fy fz [N, world frame], tension of the full-length tendon [N],
// number of cold solves.  One line per solve: "solve <thread CPU ms> <wall ms> <ok>"
// (ok: the model's own success flag), then "tip x y z" [m] of the last solve.
int main(int argc, char** argv){
    if(argc != 6){
        fprintf(stderr, "usage: %s fx fy fz tension solves\n", argv[0]);
        return 2;
    }
    // the robot of the benchmark's shipped main.cpp
    std::array<double,2> length = {0.2, 0.2};
    double youngs_modulus = 54e9;
    std::array<int,2> number_disks = {10, 10};
    std::array<double,2> pradius_disks = {10e-3, 10e-3};
    double ro = 0.7e-3;
    std::vector<Eigen::Vector3d> routing;
    for(int seg = 0; seg < 2; seg++){
        double r = pradius_disks[seg];
        routing.push_back(Eigen::Vector3d(0, r, 0));
        routing.push_back(Eigen::Vector3d(r*std::cos(-M_PI/6), r*std::sin(-M_PI/6), 0));
        routing.push_back(Eigen::Vector3d(r*std::cos(7*M_PI/6), r*std::sin(7*M_PI/6), 0));
    }
    CosseratRodModel model;
    model.setRobotParameters(length, youngs_modulus, routing, number_disks, pradius_disks, ro);
    model.setKeepInits(false);  // every solve from the default guess: cold

    Eigen::MatrixXd q(6, 1);
    q << 0, 0, 0, atof(argv[4]), 0, 0;  // tendon 4: the second segment's (0, r, 0), full length
    Eigen::Vector3d f_ext(atof(argv[1]), atof(argv[2]), atof(argv[3]));
    Eigen::Vector3d l_ext = Eigen::Vector3d::Zero();
    const int solves = atoi(argv[5]);
    Eigen::MatrixXd frames;
    for(int k = 0; k < solves; k++){
        double c0 = clock_ms(CLOCK_THREAD_CPUTIME_ID), w0 = clock_ms(CLOCK_MONOTONIC);
        bool ok = model.forwardKinematics(frames, q, f_ext, l_ext);
        double c1 = clock_ms(CLOCK_THREAD_CPUTIME_ID), w1 = clock_ms(CLOCK_MONOTONIC);
        printf("solve %.6f %.6f %d\n", c1 - c0, w1 - w0, ok ? 1 : 0);
    }
    Eigen::Vector3d tip = frames.rightCols(4).block(0, 3, 3, 1);
    printf("tip %.15e %.15e %.15e\n", tip(0), tip(1), tip(2));
    return 0;
}
"""
)


def _replace_once(text: str, old: str, new: str, what: str) -> str:
    n = text.count(old)
    if n != 1:
        raise PeerBuildError(
            f"Till's main.cpp: {what}: expected 1 occurrence of {old!r}, found {n}"
        )
    return text.replace(old, new)


def till_driver_source(main_cpp: str) -> str:
    """Till's example ``main.cpp`` (text) transformed into the timing driver (see the
    module docstring): its model and shooting function verbatim except for the gravity
    variable and the tip force, its ``main`` replaced by ``TILL_MAIN_TEMPLATE``."""
    head, sep, old_main = main_cpp.partition("int main(")
    if not sep:
        raise PeerBuildError("Till's main.cpp: no 'int main('")
    guess = re.search(r"VectorXd init_guess = [^;]*;", old_main)
    call = re.search(r"solveLevenbergMarquardt<shootingFunction>\((.*?)\);", old_main, re.S)
    if not guess or not call:
        raise PeerBuildError("Till's main.cpp: its initial guess or solver call not found")
    head = _replace_once(
        head,
        "const Vector3d g = 9.81*Vector3d::UnitX();",
        "static Vector3d g = 9.81*Vector3d::UnitX(); // gravity, set by the driver's main\n"
        "static Vector3d f_tip = Vector3d::Zero(); // tip force [N, world frame], set by main",
        "gravity",
    )
    head = _replace_once(
        head,
        "    //Find the length violation error",
        "    //Tip force (world frame) in the tip's body frame, as nbL and the tendons' forces\n"
        "    force_error += transposeMultiply(Matrix3d(Map<Matrix3d>(&Y(3,Y.cols()-1))), f_tip);\n"
        "\n    //Find the length violation error",
        "tip force",
    )
    body = TILL_MAIN_TEMPLATE.replace("@INIT_GUESS@", guess.group(0)).replace(
        "@SOLVER_ARGS@", " ".join(call.group(1).split())
    )
    return (
        "// Generated by tendonrod's bench/peers_build.py from Till's ContinuumRobotExamples\n"
        "// 01_Statics/06_Tendon_Robot_Variants/Cpp_3/main.cpp (see that script).\n"
        + head
        + TIMING_HELPERS
        + body
    )


def _eigen_shim(build_dir: str, lib: str) -> list[str]:
    """Include flags that resolve Till's ``#include "eigen/Eigen/Dense"``: its bundled
    Eigen if present, else the system Eigen through a symlink in the build folder."""
    if os.path.isdir(os.path.join(lib, "eigen", "Eigen")):
        return []
    if not os.path.isdir(os.path.join(SYSTEM_EIGEN, "Eigen")):
        raise PeerBuildError(f"no Eigen: neither {lib}/eigen nor {SYSTEM_EIGEN}")
    shim = os.path.join(build_dir, "eigen-shim")
    os.makedirs(shim, exist_ok=True)
    link = os.path.join(shim, "eigen")
    if not os.path.islink(link):
        os.symlink(SYSTEM_EIGEN, link)
    return ["-I" + shim]


def _write(path: str, text: str) -> None:
    """Write ``text`` unless the file already holds it (keeps its time for ``_compile``)."""
    if os.path.exists(path):
        with open(path) as fh:
            if fh.read() == text:
                return
    with open(path, "w") as fh:
        fh.write(text)


def _compile(cmd: list[str], inputs: list[str]) -> None:
    """Run ``cmd`` (whose output follows ``-o``) unless the output is newer than every
    input file."""
    out = cmd[cmd.index("-o") + 1]
    if os.path.exists(out) and all(os.path.getmtime(out) > os.path.getmtime(f) for f in inputs):
        return
    res = subprocess.run(cmd, capture_output=True, text=True)
    if res.returncode != 0:
        raise PeerBuildError(f"{' '.join(cmd)}\n{res.stderr[-3000:]}")


@dataclasses.dataclass
class Peers:
    """The built drivers: ``exes`` maps "till" / "rao" to an executable."""

    build_dir: str
    exes: dict
    commands: list

    def run(self, name: str, solves: int = PEER_SOLVES) -> dict:
        """``solves`` cold solves of scene ``name`` (a key of ``PEER_SCENES``) in one
        driver run: thread CPU and wall times per solve [ms], the tip of the last [m],
        and whether every solve reported success."""
        driver, args = PEER_SCENES[name]
        cmd = [self.exes[driver], *(repr(float(a)) for a in args), str(solves)]
        res = subprocess.run(cmd, capture_output=True, text=True)
        cpu, wall, ok, tip = [], [], res.returncode == 0, None
        for line in res.stdout.splitlines():
            f = line.split()
            if f and f[0] == "solve":
                cpu.append(float(f[1]))
                wall.append(float(f[2]))
                ok = ok and (len(f) < 4 or f[3] == "1")
            elif f and f[0] == "tip":
                tip = np.array([float(v) for v in f[1:4]])
        if tip is None or len(cpu) != solves:
            raise PeerBuildError(f"{' '.join(cmd)} failed: {res.stdout[-500:]}{res.stderr[-500:]}")
        return {"cpu_ms": cpu, "wall_ms": wall, "tip": tip, "ok": ok}


def build(peer_src: str, build_dir: str | None = None) -> Peers:
    """Write and compile both drivers from the checkouts under ``peer_src`` into
    ``build_dir`` (default: ``build-static`` beside ``peer_src``); raises
    ``PeerBuildError`` naming what is missing or what failed."""
    peer_src = os.path.abspath(peer_src)
    for rel in (TILL_MAIN, TILL_LIB, RAO_CPP, RAO_INC):
        if not os.path.exists(os.path.join(peer_src, rel)):
            raise PeerBuildError(f"missing {os.path.join(peer_src, rel)}")
    if shutil.which(CXX) is None:
        raise PeerBuildError(f"no {CXX}")
    build_dir = build_dir or os.path.join(os.path.dirname(peer_src), "build-static")
    os.makedirs(build_dir, exist_ok=True)
    lib = os.path.join(peer_src, TILL_LIB)
    with open(os.path.join(peer_src, TILL_MAIN)) as fh:
        till_src = till_driver_source(fh.read())
    till_cpp = os.path.join(build_dir, "till_statics_driver.cpp")
    _write(till_cpp, till_src)
    rao_cpp = os.path.join(build_dir, "rao_cosserat_driver.cpp")
    _write(rao_cpp, RAO_DRIVER)
    exes = {
        "till": os.path.join(build_dir, "till_statics_driver"),
        "rao": os.path.join(build_dir, "rao_cosserat_driver"),
    }
    gsl_c = subprocess.run(["pkg-config", "--cflags", "gsl"], capture_output=True, text=True)
    gsl_l = subprocess.run(["pkg-config", "--libs", "gsl"], capture_output=True, text=True)
    eigen_c = subprocess.run(["pkg-config", "--cflags", "eigen3"], capture_output=True, text=True)
    commands = [
        [CXX, *CXXFLAGS, "-I" + lib, *_eigen_shim(build_dir, lib), till_cpp, "-o", exes["till"]],
        [
            CXX,
            *CXXFLAGS,
            "-I" + os.path.join(peer_src, RAO_INC),
            *(eigen_c.stdout.split() or ["-I" + SYSTEM_EIGEN]),
            *gsl_c.stdout.split(),
            rao_cpp,
            os.path.join(peer_src, RAO_CPP),
            "-o",
            exes["rao"],
            *(gsl_l.stdout.split() or ["-lgsl", "-lgslcblas", "-lm"]),
        ],
    ]
    headers = [os.path.join(lib, f) for f in os.listdir(lib) if f.endswith(".h")]
    rao_inc = os.path.join(peer_src, RAO_INC)
    headers += [os.path.join(rao_inc, f) for f in os.listdir(rao_inc) if f.endswith(".h")]
    for cmd in commands:
        _compile(cmd, [f for f in cmd if f.endswith(".cpp")] + headers)
    return Peers(build_dir, exes, commands)


def check_tip(name: str, peer_tip, our_tip) -> tuple[float, float, bool]:
    """Distance [m] of the peer's tip from tendonrod's, the tolerance, and whether it is
    within (``TIP_TOL`` of the scene's peer)."""
    tol = TIP_TOL[PEER_SCENES[name][0]]
    dist = float(np.linalg.norm(np.asarray(peer_tip) - np.asarray(our_tip)))
    return dist, tol, dist <= tol


def built_peers(peer_src: str, scenes: dict, build_dir: str | None = None) -> tuple[dict, str]:
    """For bench/solve.py: build the drivers and check each peer scene of ``scenes``
    (name -> (tendonrod Scene, ...)) by its tip against tendonrod's default solve.
    Returns ({name: Peers} for the scenes that built and agree, a one-line note per scene
    that did not: why it falls back to the fixed table)."""
    import tendonrod as tr

    try:
        peers = build(peer_src, build_dir)
    except PeerBuildError as exc:
        return {}, f"peer build failed, fixed table used: {exc}"
    out, notes = {}, []
    for name, entry in scenes.items():
        if name not in PEER_SCENES:
            continue
        try:
            r = peers.run(name, 1)
        except PeerBuildError as exc:
            notes.append(f"{name}: driver failed ({exc}); fixed table used")
            continue
        dist, tol, ok = check_tip(name, r["tip"], tr.solve(entry[0]).tip_position)
        if ok and r["ok"]:
            out[name] = peers
            print(f"peer {name}: built, tip {dist:.1e} m from tendonrod's (tolerance {tol:.0e})")
        else:
            notes.append(
                f"{name}: peer tip {dist:.2e} m from tendonrod's (tolerance {tol:.0e}), "
                f"peer success flag {r['ok']}: the driver's scene is wrong; fixed table used"
            )
    return out, "; ".join(notes)


# --------------------------------------------------------------------------- stand-alone
def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--peer-src", required=True, metavar="DIR")
    ap.add_argument("--build-dir", default=None, metavar="DIR")
    ap.add_argument("--rounds", type=int, default=5, help="driver runs per scene")
    ap.add_argument("--solves", type=int, default=PEER_SOLVES, help="cold solves per run")
    args = ap.parse_args(argv)
    import tendonrod as tr

    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from solve import scenes  # noqa: E402 (solve.py imports this module at its top)

    peers = build(args.peer_src, args.build_dir)
    print(f"built in {peers.build_dir} with: {' '.join([CXX, *CXXFLAGS])}")
    print(
        f"{'scene':<24s} {'CPU ms':>8s} {'wall ms':>8s} {'tip [m]':>40s} {'vs tendonrod':>13s} ok"
    )
    for name, entry in scenes().items():
        if name not in PEER_SCENES:
            continue
        runs = [peers.run(name, args.solves) for _ in range(args.rounds)]
        cpu = statistics.median(c for r in runs for c in r["cpu_ms"])
        wall = statistics.median(w for r in runs for w in r["wall_ms"])
        tip = runs[-1]["tip"]
        dist, tol, ok = check_tip(name, tip, tr.solve(entry[0]).tip_position)
        print(
            f"{name:<24s} {cpu:8.2f} {wall:8.2f} {np.array2string(tip, precision=8):>40s} "
            f"{dist:13.2e} {'ok' if ok and all(r['ok'] for r in runs) else 'WRONG'}"
        )


if __name__ == "__main__":
    main()
