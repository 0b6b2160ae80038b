/*
 * tr_internal.h -- what the core's translation units share and the public API
 * does not show: state layouts, the solve-policy constants with their reasons,
 * and the internal functions of each layer.
 *
 * The files' layers (a file calls only into its own layer or the ones below it) are
 * listed once, in csrc/README.md; tools/check_house.py checks them.
 */
#ifndef TR_INTERNAL_H
#define TR_INTERNAL_H

#include <math.h>
#include <stddef.h>

#include "tendonrod.h"

#include "tr_data.h"

/* State layouts (docs/model.md): spatial p (3), R (9, row-major), n_b (3), m_b (3),
 * then path lengths; planar x, z, theta, n_b1, n_b3, m_b2, then path lengths. */
enum { TR_Y_P = 0, TR_Y_R = 3, TR_Y_N = 12, TR_Y_M = 15, TR_Y_LEN = 18 };
enum {
    TR_YP_X = 0,
    TR_YP_Z = 1,
    TR_YP_TH = 2,
    TR_YP_N1 = 3,
    TR_YP_N3 = 4,
    TR_YP_M = 5,
    TR_YP_LEN = 6
};

/* ------------------------------------------------------ solve-policy constants */
/* Forward-difference step for the Jacobian, scaled units: ~sqrt(machine eps). */
#define TR_FD_H 1.5e-8
/* Central-difference step for the compliance (scaled units): balances the
 * h^2 truncation (~1e-11) against round-off (~1e-16/h). */
#define TR_CD_H 3e-6
/* Largest Newton step (scaled max-norm): 10 ~ a curl of 10 rad per length. */
#define TR_MAX_STEP 10.0
/* Shared tension direction (d->shared_mode): its Jacobian column by a forward difference
 * of TR_SHARED_H of the shared level (the column is ~EI/(r^2 EA) of the others, so the
 * per-column differences of step TR_FD_H lose it in rounding), and a step cap of
 * TR_MAX_STEP or TR_SHARED_GROW times the largest tension unknown (the shared level of
 * very stiff sets grows like EA^(1/3), to 1e3-1e4 tension scales) */
#define TR_SHARED_H 1e-4
/* iterations of the shared-mode retry (steps double the shared level at most) */
#define TR_SHARED_ITER 100
/* ... and where that fails, from tendons softened to r^2 EA/EI = TR_SOFT_RATIO (solved by
 * the ordinary pipeline to 1e6-1e8) back to their own EA, in factors of at most
 * TR_STIFFEN_STEP (the shared level moves by ~STEP^(1/3)), halved (in log) down to
 * TR_STIFFEN_MIN */
#define TR_SOFT_RATIO 1e5
/* a solution of stiff tendons whose residuals fix their shared tension level no better
 * than this fraction of the largest tension is refused (its tensions are the guess's,
 * not the scene's; the suite verifies tensions to 1e-6) */
#define TR_SHARED_RESOLVE 1e-6
#define TR_RESIDUAL_NOISE 1e-13
#define TR_STIFFEN_STEP   10.0
#define TR_STIFFEN_MIN    1.01
#define TR_SHARED_GROW    1.0
/* Armijo constant of the backtracking line search. */
#define TR_ARMIJO 1e-4
/* Smallest line-search step before giving up. */
#define TR_ALPHA_MIN 1e-6
/* A stalled scaled residual below this is probably round-off, not a bad model; and the
 * largest round-off floor of the residual (tr_roundoff_floor) at which a solve counts as
 * converged above tol (TR_ROUNDOFF). */
#define TR_ROUNDOFF_HINT 1e-8
/* A Broyden step reducing the residual by less than this factor triggers a
 * fresh finite-difference Jacobian. */
#define TR_BROYDEN_RATIO 0.5
/* Smallest step (scaled max-norm) that updates the Jacobian in a lean warm solve:
 * below it the secant (f(x + dx) - f(x)) / dx is dominated by the integration's
 * round-off (~1e-14) and a Broyden update would spoil a Jacobian that later points
 * reuse. */
#define TR_LEAN_BROYDEN_MIN_STEP 1e-10
/* Condition number (1-norm, scaled) above which the Jacobian counts as singular. */
#define TR_COND_SINGULAR 1e12
/* A cold solve's last Newton Jacobian stands for the fresh one at the solution (its
 * condition estimate, polish and output Jacobian) when it was differenced at the same step
 * count within TR_J_MOVE (scaled, relative, max-norm) of the solution and its condition is
 * at most TR_COND_TRUST.  Measured over the stress suite (bench/results/error_estimate.md):
 * an updated Jacobian's condition was within 0.67x..1.95x of the fresh one's wherever it was
 * below 1e8, off by up to 7,400x above (2.3e12 against 3.2e8 near TR_COND_SINGULAR): 1e6
 * keeps six decades from the threshold.  Its other uses (the first warm solve after it,
 * inverse actuation's trial solves) need it close to the fresh one: differences of 3e-3
 * and more cost the first warm solve 1-4 iterations on the bench scenes; a move of 1e-3
 * at the same step count kept the difference below 2.3e-4 there. */
#define TR_COND_TRUST 1e6
#define TR_J_MOVE     1e-3
/* Automatic step count: initial totals for rk8 and rk4 ... */
#define TR_AUTO_RK8 2
#define TR_AUTO_RK4 16
/* ... and at least this many rk8 steps per unit of L sqrt(|F|/EI) (boundary layers
 * of width L / lambda), capped so that max_nfev stays a time bound for huge loads. */
#define TR_AUTO_PER_LAMBDA 2.0
#define TR_AUTO_MAX        256
/* ... and at least TR_AUTO_PER_TURN times that per radian the tendons turn the rod
 * (tau r l / EI, q / r): two tension-controlled tendons curling a rod 1,580 deg (27.5
 * rad) do not converge from 2 rk8 steps, from 8 they do (17 with this rule); a bend up
 * to pi keeps the minimum count (0.6 pi < 2 rk8 steps, 2.4 pi < 16 rk4 steps) ... */
#define TR_AUTO_PER_TURN 0.3
/* ... and at least TR_AUTO_PER_FRIC times that per unit of the friction's exponent
 * sum mu theta (measured: mu theta = 4.5 converges from 32 rk8 steps, not 16) */
#define TR_AUTO_PER_FRIC 4.0
/* Channel friction: the frictionless twin's stability verdict (tr_stability.c) is reported
 * only where friction changes the tensions by at most e^TR_TWIN_FRIC_MAX (~22 %) along
 * the channels: farther, the frictional state is far from any frictionless equilibrium
 * and the twin's Hessian at it is no verdict (on the stress suite, bends of 90-225 deg
 * with mu theta 1.2-3.1 gave 'unstable' twins whose frictionless solves are stable).  The
 * reproducer of a hidden instability, mu theta = 0.1 x pi/3: its twin's margin -0.091
 * EI/L against -0.088 of the frictionless solve. */
#define TR_TWIN_FRIC_MAX 0.2
/* ... and a frictional solve that fails there tries again at this many times the steps
 * (tr_solve.c) */
#define TR_FRIC_REFINE 4
/* Largest step count the step verification refines to. */
#define TR_STEP_CAP 8192
/* Step refinement aims the Richardson-predicted truncation at this fraction of tol. */
#define TR_REFINE_SAFETY 0.5
/* Fixed steps: a converged solve whose step-doubling truncation estimate exceeds this
 * many times tol is reported as TR_TRUNCATION (converged with a caveat; Python warns).
 * Between tol and this the estimate is reported without a warning: fixed steps are a
 * choice of accuracy, and 1e4 tol (1e-6 of the scales at the default tol, 0.2 um on a
 * 0.2 m rod) is where it stops being a detail.  Measured: the README robot with rk4 at
 * 4 steps is 3.4e-3 L off, at 8 steps 2.2e-4 L, rk8 at 2 steps 3.3e-6 L -- each warns. */
#define TR_FIXED_TRUNC_WARN 1e4
/* Rounds of step refinement (each at least N + 1 steps, usually one suffices). */
#define TR_REFINE_ROUNDS 16
/* A verification record vouches for a solution whose scaled unknowns moved at most this
 * much (relative, max-norm, see tr_verify_carried) from where it was measured. */
#define TR_CARRY_MAX_MOVE 0.25
/* ... with this factor of safety on the growth model's bound (measured: the growth of an
 * independent step doubling reached 0.96 of the model's along a 1x..3x load sweep). */
#define TR_CARRY_SAFETY 2.0
/* Recording pass: RK4 steps of at most this fraction of the rk8 shooting step, and
 * at most L / TR_RECORD_RK4_MIN_STEPS ... */
#define TR_RECORD_RK4_FRACTION  8.0
#define TR_RECORD_RK4_MIN_STEPS 100.0
/* ... redone with rk8 if its tip differs from the shooting tip by more than this
 * (scaled states): a guard against gross RK4 errors (unresolved boundary layers);
 * otherwise the tip node takes the shooting tip. */
#define TR_RECORD_GROSS 1e-6
/* Continuation: first step and smallest step in lambda. */
#define TR_CONT_DLAM0    0.25
#define TR_CONT_DLAM_MIN 1e-4
/* Iterations per continuation step: Newton from a near point converges in a few. */
#define TR_CONT_ITER 15
/* Polish: at most this many extra Newton steps, taken while the step exceeds
 * TR_POLISH_XTOL_FACTOR tol (relative to max(1, |x|)), or, after the step
 * verification moved the step count, while the residual exceeds
 * TR_POLISH_RES_FACTOR tol. */
#define TR_POLISH_STEPS       3
#define TR_POLISH_XTOL_FACTOR 1e3
#define TR_POLISH_RES_FACTOR  1e-2
/* A direct Newton run whose residual fell by less than 1/TR_STALL_RATIO over the
 * last TR_STALL_ITERS iterations is abandoned as stagnating (creeping damped steps:
 * on Fig. 11c with stiff tendons under twist the residual stays at ~2e-3 for 50+
 * iterations; a creep that ends in the Newton basin, as at r^2kL/3EI = 500, halves
 * the residual in ~8 iterations and is kept). */
#define TR_STALL_ITERS 8
#define TR_STALL_RATIO 0.8
/* The same test for a continuation stage, over TR_CONT_STALL_ITERS iterations (then
 * the step is halved).  A stricter test (2x over 4) stalls Fig. 12 at
 * r^2kL/EI = 1e8 at its first load stage: its stages creep for ~5 iterations and
 * then converge. */
#define TR_CONT_STALL_ITERS 6
#define TR_CONT_STALL_RATIO 0.8
/* A failed solve whose last iterate loads a tendon with more than this fraction of
 * EI/r^2 says that no equilibrium lies past that tension (load paths that need more
 * stall at 0.96-0.99 of it). */
#define TR_CURVATURE_HINT 0.9
/* a stall on a state where a taut tendon's path-length rate |w| / |w_ref| is below this
 * is put down to the tendon approaching the centre of curvature (the load paths that run
 * into tau = EI/r^2 stall at rates 0.01-0.04; ordinary bends stay above 0.5) */
#define TR_WATCH_RATE 0.1
/* A converged state with a taut tendon's rate below this is at or past the centre of
 * curvature (tr_solve.c: its verification failed there). */
#define TR_WATCH_PAST 0.01
/* Tensile loads: single shooting amplifies errors like exp(g), g = int sqrt(T/EI) ds,
 * and is verified up to g = 10 (stress suite, against collocation); above
 * TR_AUTO_SHOOT_GROWTH the model takes ceil(g / TR_AUTO_SHOOT_PER) shooting segments, so
 * each amplifies by at most e^4 (measured: 4-8 segments solve g = 15-30) */
#define TR_AUTO_SHOOT_GROWTH 11.0
#define TR_AUTO_SHOOT_PER    4.0
/* A failed solve with displacement-controlled tendons stiffer than this (r^2 EA/EI)
 * says so in its message (Fig. 12 twist fails from ~1e10 and converges at 1e8). */
#define TR_STIFF_HINT 1e6
/* Cold starts with loads above this scaled magnitude (sum of |F| L^2/EI, |M| L/EI,
 * |f| L^3/EI) go by continuation at once, in load steps of at most TR_RAMP_LOAD:
 * a direct Newton iteration can land on a looped, unstable elastica. */
#define TR_DIRECT_LOAD_MAX 6.0
#define TR_RAMP_LOAD       3.0
/* Such a cold start with the stability verdict on first tries direct Newton for at most
 * TR_DIRECT_TRY_ITER iterations, given up once the residual falls by less than
 * 1/TR_STALL_RATIO over TR_DIRECT_TRY_STALL of them (a try that converges falls by more
 * in every window of the suite; one that fails plateaus within 3-5), when its loads,
 * less the axial tension's part (the shooting growth squared: tension stiffens the rod
 * and cannot loop it), are at most TR_DIRECT_TRY_SCALE.  On the stress suite a direct
 * solve that converges at all does so in 0-9 iterations below that scale (a plain
 * cantilever at F L^2/EI = 10: 8, against 52 by continuation; axial tension of any size:
 * 0-2), and rarely above it (F L^2/EI = 12: 66).  Its answer stands only if the verdict
 * calls it stable; otherwise the load path decides, as before (an off-path answer, e.g.
 * a looped elastica, is unstable or not judged: the suite's out-of-plane load at
 * F L^2/EI = 30 lands 0.09 L from the load path's answer, not judged). */
#define TR_DIRECT_TRY_SCALE 12.0
#define TR_DIRECT_TRY_ITER  12
#define TR_DIRECT_TRY_STALL 3
/* internal: tr_branch's verdict on such a try that is not stable (never returned) */
#define TR_DIRECT_DOUBT 101
/* A continuation stage may move the tip by at most this fraction of L. */
#define TR_CONT_TIP_JUMP 0.2
/* Newton iterations of the implicit jump at a breakpoint (converges in 2-4). */
#define TR_JUMP_ITER 20
/* Iterations a lean warm solve (tr_solve_lean) may take. */
#define TR_LEAN_ITER 8

/* ------------------------------------------------------ the constants of the layers' files */
/* The policy constants used by one file each, by layer (csrc/README.md); no .c file defines
 * one of its own (tools/check_house.py).  The stability layer's are in tr_stab.h, the
 * dense QP's limits in tr_qp.h. */
/* base: tr_options.c */
/* Samples of the midpoint rule for the growth exponent. */
#define TR_GROWTH_SAMPLES 256
/* scene: tr_routing.c, tr_backbone.c, tr_tendons.c, tr_model.c */
/* Pieces must join within this fraction of L (round-off of the user's knots). */
#define TR_KNOT_TOL 1e-12
/* Composite panels per integration segment of the reference-length quadrature: |w_ref| is
 * the root of a positive quadratic in s, so 16 panels of 8 points reach round-off. */
#define TR_REF_PANELS 16
/* Relative tolerance of the pretension balance check sum(tau_p r_i) = 0. */
#define TR_BALANCE_TOL 1e-9
/* Breakpoints closer than this fraction of L are merged (round-off in user
 * arc lengths such as 0.1 * 3 vs 0.3). */
#define TR_BP_MERGE 1e-12
/* shooting: tr_watch.c */
/* Sub-steps of the walk per rod length, at least (the closest approach to 1/r is located
 * to L / TR_WATCH_STEPS or to a shooting step, whichever is finer). */
#define TR_WATCH_STEPS 32
/* outputs: tr_compliance.c */
/* The step of the forward differences over the unknowns (scaled units).  Their error is
 * the truncation h |F''| / 2 plus the residual's rounding over h: the solver's TR_FD_H
 * (1.5e-8) is rounding-bound here, with derivatives up to ~5e-7 relative off the central
 * ones on a Cosserat rod's EA / GA; 5e-8 balances the two, ~1e-7 at worst on the test
 * scenes and ~2e-8 on the Fig. 11c robot (bench/results/jacobian_actuate.md). */
#define TR_LIN_FD_H 5e-8
/* policy: tr_branch.c, tr_confirm.c */
/* A warm solve keeps the previous verdict while its scaled change times (1 + the
 * stiffness scale) stays below this fraction of the verdict's distance from zero. */
#define TR_CARRY 0.25
/* Size of the symmetry-breaking imperfection, scaled by EI/L^2 (force), EI/L (moment). */
#define TR_IMPERFECTION 1e-3
/* The imperfections tried in turn, in the tip's body frame: a force along x, y and the
 * two diagonals (a robot with tendons is not isotropic: its stable buckled branch may lie
 * between the axes), then a moment about the tangent. */
#define TR_N_IMPERFECTIONS 5
/* Shooting segments of the confirming formulation. */
#define TR_CONFIRM_SEGMENTS 8
/* Tips of two solves of one equilibrium agree to the solver tolerance (~1e-8 L);
 * distinct equilibria found so far differ by >= 1e-2 L: 1e-6 L (and 1e-6 of the
 * largest tension) separates them. */
#define TR_CONFIRM_AGREE 1e-6
/* over the driver: tr_batch.c, tr_path.c, tr_actuate.c */
/* History depth of converged points kept for the predictor (cubic: four). */
#define TR_BATCH_HIST 4
/* Newton iterations of one correction, and the largest scaled Newton step accepted. */
#define TR_PATH_ITER     12
#define TR_PATH_MAX_STEP 1.0
/* Smallest step along the path before it stops as stalled. */
#define TR_PATH_DS_MIN 1e-9
/* A step whose tangent turns by more than acos(TR_PATH_COS) is retried shorter: it may
 * have jumped to another branch. */
#define TR_PATH_COS 0.9
/* Illinois iterations locating a special point, and the arclength bracket that ends them
 * (relative to the step that contains the point). */
#define TR_PATH_REFINE     80
#define TR_PATH_REFINE_TOL 1e-13
/* An indicator still above this fraction of its values at the step's ends when the
 * bracket has shrunk jumps rather than vanishes (a singular point, not a special one). */
#define TR_PATH_JUMP 1e-3
/* A special point is located again with the steps doubled (at most this many times) until
 * its parameter moves by at most this much relative. */
#define TR_PATH_LOCATE_ROUNDS 5
#define TR_PATH_LOCATE_TOL    1e-11
/* Consecutive rejected trust-region steps after which the iteration stops: the region has
 * shrunk by 4^8 ~ 6e4 below the step refused first, so a step that still does not reduce
 * the residual means none will (a least-squares point, e.g. at a tension bound). */
#define TR_ACT_MAX_REJECTED 8
/* The first trust region (scaled controls): about a half turn of the tip. */
#define TR_ACT_DELTA0 3.0
/* The least change's stopping test (scaled controls): the step the linearised problem
 * still asks for and its stationarity residual.  The forward-difference linearisation is
 * good to ~1e-7 relative, so a tighter test chases its noise (steps of a few 1e-7 that
 * the merit then refuses); 1e-6 is 1e-8 m of a displacement at a 10 mm offset. */
#define TR_ACT_KKT_TOL 1e-6

/* ------------------------------------------------------------ small helpers */
/* Number of force/moment unknowns: 3 planar (x, z force, y moment), 6 spatial. */
static inline int tr_n_force(const tr_model *m)
{
    return m->planar ? 3 : 6;
}

/* Tension tau [N] and slack beta [m] of a displacement-controlled tendon's unknown
 * gamma: linear (semismooth) tau = tau_s max(gamma, 0), beta = l_s max(-gamma, 0), or
 * the paper's squared form tau = tau_s gamma^2 (gamma >= 0), beta = l_s gamma^2
 * (gamma < 0); tau_s = EI/(r L), l_s = r with r the largest offset of a
 * displacement-controlled tendon, so a unit of gamma changes the path length by ~r on
 * either side of the switch and the Jacobian is balanced. */
static inline void tr_tension_of_gamma(const tr_model *m, int slack_model, double g, double *tau,
                                       double *beta)
{
    if (slack_model == TR_SLACK_SQUARED) {
        *tau = g > 0.0 ? m->tau_s * g * g : 0.0;
        *beta = g < 0.0 ? m->len_s * g * g : 0.0;
    } else {
        *tau = g > 0.0 ? m->tau_s * g : 0.0;
        *beta = g < 0.0 ? -m->len_s * g : 0.0;
    }
}

/* Its inverse: gamma of a tension tau [N] (if > 0) or else a slack beta [m]. */
static inline double tr_gamma_of_tension(const tr_model *m, int slack_model, double tau,
                                         double beta)
{
    const int sq = slack_model == TR_SLACK_SQUARED;
    if (tau > 0.0) return sq ? sqrt(tau / m->tau_s) : tau / m->tau_s;
    if (beta > 0.0) return sq ? -sqrt(beta / m->len_s) : -beta / m->len_s;
    return 0.0;
}

/* Force sum_i tau_i t0_i and moment sum_i tau_i r_i(0) x t0_i [N, N m] of the tendons
 * pulling on the base section of the straight robot (tensions tau (nt), negative
 * ones counted as 0): the part of the base reaction the tendons carry. */
static inline void tr_tendon_pull_sum(const tr_model *m, const double *tau, double tn[3],
                                      double tm[3])
{
    int i, c;
    tn[0] = tn[1] = tn[2] = tm[0] = tm[1] = tm[2] = 0.0;
    for (i = 0; i < m->nt; i++) {
        const double t = tau[i] > 0.0 ? tau[i] : 0.0;
        for (c = 0; c < 3; c++) {
            tn[c] += t * m->tendon[i].t0[c];
            tm[c] += t * m->tendon[i].rt0[c];
        }
    }
}

/* Friction (tr_friction.c).  The friction states follow the path lengths: the first is at
 * n_base + ndisp in the shooting layout, n_base + nt in the recording one. */
static inline int tr_fric_base(const tr_model *m, const tr_data *d)
{
    return m->n_base + (d->rec ? m->nt : m->ndisp);
}
/* Tendon i's tension [N] at the state y: its tension at the actuator d->tau[i], less its
 * friction deficit (never below 0). */
static inline double tr_tension_at(const tr_model *m, const tr_data *d, int i, const double *y)
{
    const int f = m->tendon[i].fric_index;
    double tau = d->tau[i];
    if (f < 0) return tau;
    tau -= y[tr_fric_base(m, d) + f];
    return tau > 0.0 ? tau : 0.0;
}
/* The tensions of every tendon at y (d->tau itself without friction, else d->tau_here). */
const double *tr_tensions_at(const tr_model *m, const tr_data *d, const double *y);
/* dst's friction (a model of the same scene, compiled without it) set to src's. */
void tr_friction_copy(tr_model *dst, const tr_model *src);
/* The exponent of the friction's tension change, summed over the frictional tendons:
 * mu theta with theta the turning a tendon gives the rod (q / r for a retraction, tau r l
 * / EI for a tension); a tension changes like e^(mu theta) along its channel. */
double tr_friction_exponent(const tr_model *m);
/* The right-hand side's friction: per frictional taut tendon, TR_FRIC_NCOL numbers (its
 * state slot, slide mu, tension / |w|, t (3), r (3), a_i (3), tau'); the friction loads solve
 * the implicit equation by fixed-point iteration to TR_FRIC_TOL (relative) within
 * TR_FRIC_ITER iterations (each contracts by ~ mu tau r^2 / EI, at most mu r kappa). */
#define TR_FRIC_NCOL 13
#define TR_FRIC_TOL  1e-15
#define TR_FRIC_ITER 100
/* A fixed step across a reversal of a frictional tendon's normal load (a kink of
 * |tau t^'|) is split there, the reversal located to TR_KINK_TOL of the step within
 * TR_KINK_ITER trials (tr_integrate.c): a step across it would lose its order (an error
 * ~h^2, 5e-9 of the tip angle at 8192 rk8 steps) */
#define TR_KINK_TOL  1e-10
#define TR_KINK_ITER 60
/* the cost of a frictional tendon in the right-hand side, per tendon, relative to the
 * frictionless evaluation (measured, bench/friction_cost.py: one tendon +0.87 planar, +0.67
 * spatial; three +0.60 each) */
#define TR_FRIC_WORK 0.8

/* The cost of one right-hand-side evaluation of the model's formulation [work units, see
 * TR_DEFAULT_MAX_WORK]; measured: planar Kirchhoff 33 ns + 28 ns per tendon; planar
 * Cosserat 90 ns with one tendon; spatial Kirchhoff 185 ns, Cosserat 300 ns with three
 * tendons (+4 % per tendon beyond); a frictional tendon adds the fixed-point solves and
 * the normals of the kink test, TR_FRIC_WORK per tendon of the formulation's base cost.
 * A formula of the model's counts, inline: the model (tr_model.c) and its friction
 * states (tr_friction.c) both set it. */
static inline double tr_rhs_work(const tr_model *m)
{
    const double base = m->planar ? (m->kirchhoff ? 1.0 : 1.85) + 0.85 * m->nt
                                  : (m->kirchhoff ? 4.0 : 7.5) + 0.5 * m->nt;
    return base * (1.0 + TR_FRIC_WORK * m->nfric);
}

/* The cost of the linear algebra of a Newton step on k unknowns [work units, see
 * TR_DEFAULT_MAX_WORK; one unit ~27-30 ns of CPU measured here with tr.solve at 2000
 * steps].  GSL's LU with its own CBLAS (which skips zero multipliers), CPU time: a dense
 * k x k matrix ~0.15 ns per k^3 (k = 300..1140; 0.13-0.28 on Broyden-updated Jacobians
 * of 996 unknowns), the sparse Jacobians of multiple shooting 0.04-0.1 ns per k^3 at a
 * fraction 0.009-0.044 of nonzeros (k = 109..1332, planar and spatial): TR_LU_WORK k^3
 * times min(1, TR_LU_SPARSE_BASE + TR_LU_SPARSE_SCALE x the fraction) covers both.  One
 * pair of triangular solves: 0.8-1.3 ns per k^2.  Counted in tr_lu_factor and the solves
 * (tr_newton.c), the path's bordered LU (tr_path.c) and the hybrid method's QR
 * (tr_hybrid.c). */
#define TR_LU_WORK         0.006
#define TR_LU_SPARSE_BASE  0.2
#define TR_LU_SPARSE_SCALE 8.0
#define TR_TRSV_WORK       0.05
static inline double tr_lu_work(int k, double nonzero_fraction)
{
    const double f = TR_LU_SPARSE_BASE + TR_LU_SPARSE_SCALE * nonzero_fraction;
    return TR_LU_WORK * (f < 1.0 ? f : 1.0) * (double)k * (double)k * (double)k;
}
/* The fraction of nonzeros of the k x k matrix a (row stride tda). */
static inline double tr_nonzero_fraction(const double *a, int k, size_t tda)
{
    long nnz = 0;
    int i, j;
    for (i = 0; i < k; i++)
        for (j = 0; j < k; j++) nnz += a[(size_t)i * tda + j] != 0.0;
    return k > 0 ? (double)nnz / ((double)k * k) : 1.0;
}
static inline double tr_trsv_work(int k)
{
    return TR_TRSV_WORK * (double)k * (double)k;
}
/* Largest number of solve pairs (J, J^T) of the 1-norm condition estimate (Hager's
 * iteration converges in 2-3 in practice; LAPACK's dlacon stops at 5). */
#define TR_COND_EST_ITERS 5

/* tr_model.c: the same scene compiled with nshoot shooting segments (the formulation,
 * planar or spatial, kept), or NULL (msg says why); the point-load sums at the
 * breakpoints (bpF, bpM) from m->load. */
tr_model *tr_model_reshoot(const tr_model *m, const tr_options *opt, int nshoot, char *msg,
                           size_t msglen);
void tr_sum_breakpoint_loads(tr_model *m);

/* tr_inputs.c: the model a solve reads, given the model and the workspace passed to an
 * entry point: the workspace's view of its inputs when m is its model (or already that
 * view); another model as it is (the entry point's check then refuses it). */
#define TR_IN(m, d) ((m) == (d)->model ? (d)->vm : (m))
/* 1 when d is a workspace of m (its model or its view). */
#define TR_OWNS(m, d) ((m) == (d)->model || (m) == (d)->vm)
/* tr_inputs.c: the view of a new workspace (tr_data_alloc; 0, or -1 out of memory) and its
 * arrays freed; the values of src (a view or a model of the same scene, perhaps another
 * segmentation: the confirmation's) copied into dst's view; a design parameter (kind,
 * index) of the view set to its value + delta with what follows from it (the tendon's
 * base frame and reference length, every rest length), the scales kept so that the
 * unknowns keep their meaning -- TR_OK, or TR_EINVAL when the perturbed tendon set has
 * no rest lengths (the view then restored) -- and the view restored. */
int tr_inputs_alloc(const tr_model *m, tr_data *d);
/* tr_data.c: the confirming formulation of a workspace (d->confirm_m, d->confirm_d): the
 * scene with TR_CONFIRM_SEGMENTS shooting segments (twice the model's from there on), none
 * beyond TR_MAX_SHOOTING_SEGMENTS; 0, or -1 (msg says why). */
int tr_data_alloc_confirm(const tr_model *m, tr_data *d, char *msg, size_t msglen);
/* tr_inputs.c: the workspace's own view for a setter (a perturbation undone first), or
 * NULL with a message when d is not m's workspace (or a nested one). */
tr_model *tr_inputs_view(const tr_model *m, tr_data *d, char *msg, size_t msglen);
void tr_inputs_free(tr_data *d);
void tr_inputs_copy(tr_data *dst, const tr_model *src);
int tr_inputs_perturb(tr_data *d, int kind, int index, double delta);
void tr_inputs_restore(tr_data *d);

/* tr_target.c: the scaled residual of row `row` of the model's tip target at the end
 * state y (target rows: angle [rad], position / L, direction in log coordinates [rad]);
 * and the displacement [m] that target tendon i's solution needs (its length constraint
 * solved for q, from its path-length excess len [m] at its anchor and the tension and
 * slack set in d). */
double tr_target_residual(const tr_model *m, const double *y, int row);
double tr_target_displacement(const tr_model *m, const tr_data *d, int i, double len);

/* tr_confirm.c: a TR_OFFPATH equilibrium in d->x confirmed (TR_CONFIRMED) or not
 * (TR_OFFPATH) by a cold solve with another shooting formulation, a stage the driver runs
 * in three steps.  tr_confirm_begin notes the equilibrium (tip, the message so far) in *c
 * and sets up the second formulation (d->confirm_m, d->confirm_d): TR_CONTINUE, or the
 * status to return (TR_OFFPATH, message set; d->stop when the budget or an interrupt
 * stopped it).  The driver then solves d->confirm_m cold in d->confirm_d, and
 * tr_confirm_judge compares that solve (its status st) with the noted equilibrium:
 * TR_CONFIRMED or TR_OFFPATH, the message says which; TR_EINTERRUPTED. */
typedef struct tr_confirm {
    int segments;          /* shooting segments of the second formulation */
    double tip[12];        /* the equilibrium's tip position (3) and rotation (9) */
    char first[TR_MSGLEN]; /* the message before the confirmation */
} tr_confirm;
int tr_confirm_begin(const tr_model *m, tr_data *d, tr_confirm *c);
int tr_confirm_judge(const tr_model *m, tr_data *d, const tr_confirm *c, int st);

/* Body-frame offset r, r' and r'' (x, y components; z is 0) of tendon i (td) with a
 * general route at s on integration segment seg (tr_routing.c's tables). */
static inline void tr_route_eval(const tr_model *m, const tr_tendon *td, int i, int seg, double s,
                                 double r[2], double rp[2], double rpp[2])
{
    if (td->route == TR_ROUTE_HELIX) {
        const double rho = td->a * s + td->b, w = td->twist, ph = td->phi + w * s;
        const double c = cos(ph), sn = sin(ph);
        r[0] = rho * c;
        r[1] = rho * sn;
        rp[0] = td->a * c - rho * w * sn;
        rp[1] = td->a * sn + rho * w * c;
        rpp[0] = -2.0 * td->a * w * sn - rho * w * w * c;
        rpp[1] = 2.0 * td->a * w * c - rho * w * w * sn;
    } else {
        const double *row = m->route + TR_RT_NCOL * m->seg_piece[seg * m->nt + i];
        const double *p = row + TR_RT_P, h = s - row[TR_RT_S0];
        r[0] = p[0] + h * (p[1] + h * (p[2] + h * p[3]));
        r[1] = p[4] + h * (p[5] + h * (p[6] + h * p[7]));
        rp[0] = p[1] + h * (2.0 * p[2] + 3.0 * h * p[3]);
        rp[1] = p[5] + h * (2.0 * p[6] + 3.0 * h * p[7]);
        rpp[0] = 2.0 * p[2] + 6.0 * h * p[3];
        rpp[1] = 2.0 * p[6] + 6.0 * h * p[7];
    }
}

/* tr_routing.c: the routing rows read into m->route and the tendons' route and twist
 * (TR_OK or TR_EINVAL with a message naming the row); the per-segment piece table
 * m->seg_piece after the breakpoints (TR_OK or TR_ENOMEM); r, r' of any tendon. */
int tr_read_routes(tr_model *m, const double *routes, int nroute, char *msg, size_t msglen);
int tr_route_pieces(tr_model *m);
void tr_tendon_offset(const tr_model *m, int i, int seg, double s, double r[3], double rp[3]);

/* tr_backbone.c: the sections (nsec rows) read into m->sec, m->nsec and m->precurved
 * (TR_OK or TR_EINVAL with a message); m->seg_rod of every integration segment (after the
 * breakpoints); tendon t's base tangent t0 and r(0) x t0 in the unstressed robot; its
 * reference path length [m] from the base to its anchor in the unstressed robot; and the
 * check that no tendon offset reaches the precurvature's centre (TR_OK or TR_EINVAL). */
int tr_read_sections(tr_model *m, const double *sections, int nsec, char *msg, size_t msglen);
void tr_fill_segment_rods(tr_model *m);
void tr_tendon_base_frame(const tr_model *m, int i);
/* tr_backbone.c: the same for a linear tendon of the straight robot (from its a, b, cphi,
 * sphi and wref alone: usable before the sections and routes are read). */
void tr_tendon_base_frame_straight(tr_tendon *t);
/* tr_backbone.c: tendon i's tangent in the unstressed robot on segment k at s, w_ref = e3 +
 * u* x r + r' (body frame, not normalised). */
void tr_tendon_wref(const tr_model *m, int i, int k, double s, double w[3]);
double tr_reference_length(const tr_model *m, int i);
int tr_check_routing(const tr_model *m, char *msg, size_t msglen);

/* tr_tendons.c: rest lengths that give the pretensions (TR_OK, TR_EPRETENSION or
 * TR_EINVAL with a message), and the check for opposing inextensible tendons on a
 * Kirchhoff backbone (TR_OK, TR_EINDETERMINATE or TR_ENOEQUILIBRIUM). */
int tr_rest_lengths(tr_model *m, char *msg, size_t msglen);
int tr_check_indeterminate(const tr_model *m, char *msg, size_t msglen);

/* tr_poll.c: the monotonic wall clock [s]; the start of a solve's budget; whether to
 * go on (TR_OK) or stop (TR_EBUDGET, TR_EINTERRUPTED, then sticky in d->stop). */
double tr_clock(void);
void tr_poll_start(tr_data *d);
int tr_poll(tr_data *d);
/* Fixed-step loops poll every TR_POLL_STEPS + 1 steps (a power of two, minus one). */
#define TR_POLL_STEPS 255

/* tr_error.c: printf into a message buffer (NULL or empty: nothing), and into
 * d->message. */
void tr_msgf(char *msg, size_t len, const char *fmt, ...);
void tr_set_message(tr_data *d, const char *fmt, ...);

/* tr_rod.c */
int tr_rhs(double s, const double y[], double dyds[], void *params);
/* tr_section.c */
/* Unit tangent of tendon i at s (body frame) and its offset r (body frame), for the
 * state y (either layout). */
void tr_tendon_tangent(const tr_model *m, int i, double s, const double *y, double that[3],
                       double r[3]);
/* Tendon pulls across a section (see tr_section.c). */
void tr_section_pulls(const tr_model *m, const double *tau, int seg, double s, const double nb[3],
                      const double mb[3], double fn[3], double fm[3], double *J6);
/* Pose (p (3), R (9)), internal force and moment (world) of a state y. */
void tr_state_world(const tr_model *m, const double *y, double p[3], double R[9], double n[3],
                    double mom[3]);

/* tr_integrate.c: integrate y over [s0, s1] on segment d->seg (layout d->rec) with
 * `method` (tr_integrator) in nsteps fixed steps (ignored by TR_ADAPTIVE). */
int tr_integrate_with(const tr_model *m, tr_data *d, int method, double s0, double s1, int nsteps,
                      double *y);
/* ... with the workspace's integrator. */
int tr_integrate(const tr_model *m, tr_data *d, double s0, double s1, int nsteps, double *y);
int tr_segment_steps(const tr_model *m, const tr_data *d, int seg);

/* tr_residual.c */
/* 1 when y holds the end state of the shooting evaluation at the unknowns x at the
 * current step count (and f_of_y its residual). */
int tr_holds_end_state(const tr_data *d, const double *x);
/* After evaluations elsewhere (whose caller saved y in ysave first): y is the end state
 * of x again, f its residual. */
void tr_restore_end_state(const tr_model *m, tr_data *d, const double *x, const double *f);
/* Tensions and slacks (d->tau, d->beta) of the unknowns x. */
void tr_set_tensions(const tr_model *m, tr_data *d, const double *x);
/* Base state y (dim entries) from the unknowns x, tensions already set. */
void tr_init_state(const tr_model *m, const tr_data *d, const double *x, double *y, int dim);
/* The jump of the state at interior breakpoint b. */
void tr_apply_jump(const tr_model *m, const tr_data *d, int b, double *y);
/* Magnitude of all external loads, scaled by EI/L^2 (forces) and EI/L (moments). */
double tr_load_scale(const tr_model *m);
/* Offset of shooting node j (1..M-1) in the unknowns and residuals; scale of its
 * state component c. */
int tr_node_off(const tr_model *m, int j);
double tr_node_scale(const tr_model *m, int c);
/* Forward difference of the residual along unknown j at x (residual f0 there) into
 * col[i * stride], i < k; a trial point whose residual is not finite is retried
 * backwards if `backward`.  Uses d->xt, d->ft. */
int tr_fd_column(const tr_model *m, tr_data *d, const double *x, const double *f0, int j,
                 double *col, size_t stride, int backward);

/* tr_guess.c */
/* Cold start into d->x: the straight-robot guess or the shape pass's, whichever has
 * the smaller residual; node unknowns from the shape. */
void tr_cold_start(const tr_model *m, tr_data *d);
/* Scaled unknowns x from a physical guess g (6 + 2 nt), nodes integrated from it.
 * Returns TR_OK or TR_EINVAL (non-finite unknowns; message set). */
int tr_unknowns_from_guess(const tr_model *m, tr_data *d, const double *g, double *x);

/* The convergence tolerance of the Newton layer: opt.tol, or a stage's own (tol_override,
 * set by the driver; the options stay as the caller gave them). */
static inline double tr_tol(const tr_data *d)
{
    return d->tol_override > 0.0 ? d->tol_override : d->opt.tol;
}

/* tr_error.c: the message of a solve that converged to its residual's round-off floor
 * (TR_ROUNDOFF), the scaled residual above tol but below the floor. */
void tr_message_floor(char *msg, size_t len, int nit, double residual, double tol, double floor);

/* tr_newton.c */
/* The round-off floor of the scaled residual at the last evaluation (d->tau, d->x): the
 * unit round-off times the largest terms the residual sums.  tr_solve_test's second rule:
 * a residual at or below it has converged (above tol: TR_ROUNDOFF). */
double tr_roundoff_floor(const tr_model *m, const tr_data *d);
/* Reset the counters and the per-solve state of d for a solve at `steps` steps. */
void tr_solve_reset(const tr_model *m, tr_data *d, int steps);
/* Forward-difference Jacobian at d->x (d->f) into d->J. */
int tr_fd_jacobian(const tr_model *m, tr_data *d);
/* LU of d->J into d->LU (0, or -1 if singular) and solve with it. */
int tr_lu_factor(tr_data *d);
int tr_lu_solve(tr_data *d, const double *rhs, double *res);
/* 1-norm condition number of d->J. */
double tr_jacobian_cond(tr_data *d);
/* Newton/Broyden from the current point until converged, max_iter, or stagnation
 * (residual down by less than 1/ratio over the last `stall` iterations). */
int tr_newton_run(const tr_model *m, tr_data *d, int max_iter, int stall, double ratio);

/* tr_hybrid.c: GSL hybridsj on the same residual and Jacobian. */
int tr_hybrid_run(const tr_model *m, tr_data *d, int max_iter);

/* tr_continuation.c: from the unloaded straight robot, ramp the actuation, then the
 * loads.  Continuation steps use full Newton (fresh Jacobian every iteration): a
 * Broyden Jacobian carried across a taut/slack switch misleads the step. */
int tr_continuation(const tr_model *m, tr_data *d);
/* Ramp *lamp (d->lam_act, lam_load, lam_hom or lam_imp) from its solved value to 1 with
 * an adaptive step (halved on failure, doubled on success, at most dmax) and a secant
 * predictor; a stage whose tip jumps by more than TR_CONT_TIP_JUMP L is refused (but for
 * the actuation), and with d->ramp_stable one that ends unstable.  TR_OK, or a failure with the message naming `what`. */
int tr_ramp(const tr_model *m, tr_data *d, double *lamp, const char *what, double dmax);
/* tr_options.c: the growth exponent int_0^L sqrt(N(s)/EI) ds of the shooting
 * sensitivities under the tensile part N > 0 of the axial loads (reference
 * configuration), and the shooting segments it needs (1 up to TR_AUTO_SHOOT_GROWTH) */
double tr_shooting_growth(const tr_model *m);
int tr_auto_segments(double growth);
/* tr_newton.c: the weight of tendon i in the shared tension direction of the
 * displacement-controlled tendons (their tensions in proportion, with no net moment about
 * the centre line: 1 projected onto the null space of the offsets); 0 if it has none */
double tr_shared_weight(const tr_model *m, int i);
/* the tension [N] by which the shared level of the solution in d->x can move before its
 * residuals exceed the tolerance (or the residual reached): how well they fix it */
double tr_shared_resolution(const tr_model *m, tr_data *d);
/* the work budget of a solve: Options.max_work, whatever the formulation (the dense LU of
 * many shooting segments is counted as the work it is) */
double tr_work_budget(const tr_data *d);
/* tr_watch.c: the smallest path-length rate of a taut tendon on the state of x (at the
 * current continuation parameters), kept in d->watch_* when below the last kept one or
 * when keep is 2 (a fresh record, of a converged state: the rate signed along the
 * tendon's unstressed direction, negative past the centre of curvature; else its
 * magnitude); returns that rate, NaN if the state cannot be integrated */
double tr_watch_curvature(const tr_model *m, tr_data *d, const double *x, int keep);
/* the message part naming the tendon that would pass the centre of curvature, from
 * d->watch_*, if its rate fell below TR_WATCH_RATE; 0 if there is none */
int tr_watch_message(const tr_model *m, const tr_data *d, char *buf, size_t len);
/* the same for the converged state of x alone (a fresh record; the message places it by
 * `where`, e.g. "there"): the one rule by which a load path that ends at a singular point,
 * or a solve whose verification failed, names a tendon at or past the centre of
 * curvature; 0 if no taut tendon's rate is below TR_WATCH_RATE there */
int tr_watch_named(const tr_model *m, tr_data *d, const double *x, const char *where, char *buf,
                   size_t len);
/* tr_branch.c: the stability stage of a solve that converged to status (from a cold
 * start: cold); returns the status the solve goes on with. */
int tr_branch(const tr_model *m, tr_data *d, int status, int cold);
/* Keep the verdict of a successful solve for the next warm one. */
void tr_branch_keep(const tr_model *m, tr_data *d);
/* The verdict of a lean solve (tr_solve_lean) that converged: 1 when it may stand (kept
 * for the next), 0 when it is unstable and the full solve must take over. */
int tr_branch_lean(const tr_model *m, tr_data *d);

/* tr_inertia.c: a symmetric block-tridiagonal matrix (nblk blocks of nb <= TR_BTD_MAXB:
 * D (nblk x nb^2) diagonal blocks, E (nblk x nb^2) the block coupling j to j + 1),
 * a diagonal M (nblk nb), and nbord bordered columns B ((nblk nb) x nbord, row-major)
 * with compliances cb (nbord; 0: a constraint); the rest is workspace of the same
 * sizes (P, Pe, Pv, U: the factors; X: A^-1 B; S, Se, Sv: the Schur complement). */
#define TR_BTD_MAXB 6
typedef struct {
    int nblk, nb, nbord;
    double *D, *E, *Mw, *B, *cb;
    double *Pe, *Pv, *U, *X, *S, *Se, *Sv;
} tr_btd;
/* The number of eigenvalues of the bordered pencil (H, M) below lam (*singular: a
 * pivot was zero, no count). */
int tr_btd_count(tr_btd *w, double lam, int *singular);
/* X = (H - lam M)^-1 X (n x ncol) with the factors of the last tr_btd_count. */
void tr_btd_solve(tr_btd *w, double *X, int ncol);
/* The smallest eigenvalue of the bordered pencil (below0: the count at 0 is > 0). */
double tr_btd_smallest(tr_btd *w, int below0);

/* tr_stab_energy.c: the scale of the load-induced stiffness in the second variation, by
 * EI/L: the loads' (tr_load_scale) and each tendon's tension times its offset,
 * tau r L / EI (a tendon's pull and its pressure on the ducts cancel but for terms of
 * its offset: a centre-line tendon adds nothing, whatever its tension). */
double tr_stiffness_scale(const tr_model *m, const tr_data *d);
/* tr_data.c: the stability test's workspace, freed with the data */
void tr_stab_free(struct tr_stab_ws *w);

/* tr_verify.c */
/* Automatic initial step count of the scene. */
int tr_auto_steps(const tr_model *m, const tr_data *d);
/* Step doubling until the truncation estimate is <= tol (steps = 0); a verified count
 * is recorded (x_ver, est_ver, steps_ver). */
int tr_verify_steps(const tr_model *m, tr_data *d);
/* 1 when the workspace's verification record vouches for the current solution without
 * a new verification (d->truncation then holds the carried bound), else 0. */
int tr_verify_carried(const tr_model *m, tr_data *d);
/* How far x moved from x0: max_i |x_i - x0_i| / max(1, |x0_i|) (scaled unknowns, k). */
double tr_rel_move(const double *x, const double *x0, int k);
/* Fixed steps (steps > 0, a fixed-step integrator): the step-doubling estimate of the
 * converged solution's truncation error into d->truncation, never acted on; above
 * TR_FIXED_TRUNC_WARN tol a success becomes TR_TRUNCATION with a message that says so. */
int tr_verify_fixed(const tr_model *m, tr_data *d, int status);
/* Full Newton steps from a converged point while the step is still large. */
void tr_polish(const tr_model *m, tr_data *d);

/* ------------------------------------------------------------ dynamics (tr_dyn.c) */
/* A time step of the dynamics is a boundary-value problem in s on a fixed grid: the
 * spatial right-hand side (tr_rod.c) reads this context from d->dyn.  Every time
 * derivative is discretised as y_t = c0 y + y_h (BDF-alpha), with the history y_h of
 * each quantity kept per stage point of the fixed-step RK4 grid (the k-th right-hand-side
 * evaluation of a residual evaluation is the k-th point).  Per point, TR_DH_N numbers:
 * p (3) world, R (9) row-major, q (3) body-frame velocity, w (3) angular velocity,
 * v (3), u (3) strains, v_s (3), u_s (3) their s-derivatives, then the densities of the
 * kinetic and elastic energy [J/m] and of the dissipated power [W/m]. */
enum {
    TR_DH_P = 0,
    TR_DH_R = 3,
    TR_DH_Q = 12,
    TR_DH_W = 15,
    TR_DH_V = 18,
    TR_DH_U = 21,
    TR_DH_VS = 24,
    TR_DH_US = 27,
    TR_DH_NHIST = 30, /* the entries with a time history */
    TR_DH_EK = 30,
    TR_DH_EE = 31,
    TR_DH_PD = 32,
    TR_DH_N = 33
};
typedef struct tr_dyn_ctx {
    double c0;          /* y_t = c0 y + y_h [1/s]; 0 with hist all zero: the static problem */
    double eta;         /* Kelvin-Voigt retardation time [s]: n = K_se (v - v* + eta v_t) */
    double rhoA;        /* mass per length [kg/m] */
    double rhoJ[3];     /* rotary inertia per length about the body axes [kg m] */
    double drag;        /* air drag: body-frame force per length -drag q_i |q_i| [N s^2/m^3] */
    const double *hist; /* (npt x TR_DH_N) y_h at each stage point (first TR_DH_NHIST) */
    double *cur;        /* (npt x TR_DH_N) the current evaluation's values */
    int npt;            /* stage points of one residual evaluation */
    int k;              /* the next stage point */
} tr_dyn_ctx;
/* Stage points of one residual evaluation of a fixed-step RK4 model (4 per step). */
int tr_dyn_points(const tr_model *m, const tr_data *d);

/* tr_dyn_rhs.c: the spatial right-hand side's hooks (see there) */
int tr_dyn_strains(const tr_model *m, const tr_data *d, double s, const double *y, const double *sg,
                   const double *us, int pc, double du[3], double u[3], double v[3], double *ev3);
void tr_dyn_loads(const tr_data *d, const double *y, const double sg[], int coupled, double rhs[6],
                  double sc, const double sr[3], double sr2, const double RR0[9],
                  const double TQ[9], const double QQ[9], const double TT[9]);
void tr_dyn_store(const tr_data *d, const double *dy, const double sg[]);

#endif
