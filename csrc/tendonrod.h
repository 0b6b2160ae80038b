/*
 * tendonrod.h -- public API of the Cosserat-rod/tendon solver (pure C99 + GSL).
 *
 * A scene (rod, tendons, point loads, distributed load) is compiled once into
 * an immutable tr_model; every mutable buffer of a solve lives in a tr_data
 * workspace allocated for that model.  Solver functions read the model and
 * write the data:  int tr_solve(const tr_model *m, tr_data *d, ...).
 * The model is constant after compilation: the values that change between calls
 * (actuation, pretension, loads, friction coefficients, the target, a linearisation's
 * design perturbation) are the workspace's inputs (tr_data_set_values, ...).  One
 * compiled model serves every thread of a batch or sweep read-only; each thread owns
 * its data.  There is no global state.
 *
 * Conventions (docs/model.md): SI units, radians.  Base at the origin, base frame =
 * world frame, undeformed rod along +z.  R is body-to-world, stored row-major.
 * Tendon i runs at the body-frame offset r_i(s) = (a_i s + b_i)(cos phi_i,
 * sin phi_i, 0) and is anchored at s = t_i <= L.  q > 0 retracts a tendon.
 *
 * Status codes: 0 success, > 0 finished with a caveat, < 0 failure;
 * tr_strerror() names each, and tr_data_message() says what happened and what
 * to do about it.
 */
#ifndef TENDONROD_H
#define TENDONROD_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The C library's version (libtendonrod's soname carries major.minor: 0.x makes no ABI
 * promise between minor versions).  0.2: the workspace is opaque (accessors), the values
 * that change between calls are the workspace's inputs (tr_data_set_*); CHANGELOG.md. */
#define TR_VERSION_MAJOR 0
#define TR_VERSION_MINOR 2
#define TR_VERSION_PATCH 0

/* ---------------------------------------------------------------- status */
enum tr_status {
    TR_OK = 0,
    TR_TRUNCATION = 1,      /* converged, but the step-doubling truncation estimate
                                stayed above tol at the step cap (automatic steps), or
                                above TR_FIXED_TRUNC_WARN tol (fixed steps) */
    TR_ILLCONDITIONED = 2,  /* converged, but the final Jacobian is nearly singular
                                (tensions may be poorly determined) */
    TR_OFFPATH = 3,         /* converged by a direct solve after load continuation from
                                the unloaded robot stalled: an equilibrium, but possibly not
                                the one reached by loading (e.g. a looped rod under a large
                                tensile load), not confirmed by a second formulation; NOT
                                counted as success (TR_SUCCEEDED) */
    TR_CONFIRMED = 4,       /* as TR_OFFPATH, but a cold solve with another shooting
                                formulation reaches the same equilibrium: a success */
    TR_UNSTABLE = 5,        /* converged, but to an unstable equilibrium, and no stable one
                                was reached from the guess, along the load path or past a
                                symmetric bifurcation on it (tr_branch.c); NOT counted as
                                success (Options.accept_unstable: such a solve succeeds) */
    TR_FRICTION_HELD = 6,   /* converged with channel friction (whose stability is not
                                tested), but the frictionless twin of the state (mu = 0, the
                                same tensions) is unstable: friction alone holds it, if it
                                does; a success with a caveat (d->stab_twin) */
    TR_ROUNDOFF = 7,        /* converged to the residual's round-off floor: the iteration
                                made no more progress with the scaled residual above tol but
                                below the floor (the unit round-off times the largest internal
                                force and moment the residual sums, in EI/L^2 and EI/L), where
                                it cannot be told from zero; a success with a caveat */
    TR_CONTINUE = 100,      /* iteration in progress (tr_solve_iterate/test only) */
    TR_EINVAL = -1,         /* invalid model or option value */
    TR_ENOMEM = -2,         /* allocation failed */
    TR_EMAXITER = -3,       /* iteration cap reached */
    TR_EMAXFEV = -4,        /* function-evaluation cap reached */
    TR_ENOPROGRESS = -5,    /* line search found no decrease of the residual */
    TR_ENONFINITE = -6,     /* integration produced Inf/NaN */
    TR_ESINGULAR = -7,      /* singular Jacobian */
    TR_EINDETERMINATE = -8, /* statically indeterminate tendon set */
    TR_ENOEQUILIBRIUM = -9, /* the prescribed displacements admit no equilibrium */
    TR_EPRETENSION = -10,   /* pretension not meaningful for this tendon set */
    TR_EINTEGRATOR = -11,   /* adaptive integrator failed (step underflow / cap) */
    TR_ECONTINUATION = -12, /* continuation could not reach the full load */
    TR_EBUDGET = -13,       /* the work budget (max_work or max_time) ran out */
    TR_EINTERRUPTED = -14   /* stopped by the caller's poll hook (e.g. Ctrl-C) */
};

const char *tr_strerror(int status);

/* A status whose solution can be reported as the answer: converged, with at most a
 * caveat about accuracy or conditioning.  TR_OFFPATH is excluded: its equilibrium is
 * real but may not be the one the loading reaches, so it is handed back as data with
 * success = false (and its message), never as a success. */
#define TR_SUCCEEDED(status)                                                                       \
    ((status) >= 0 && (status) != TR_OFFPATH && (status) != TR_UNSTABLE && (status) != TR_CONTINUE)

/* --------------------------------------------------------------- options */
enum tr_integrator { TR_RK4 = 0, TR_RK8 = 1, TR_ADAPTIVE = 2 };
enum tr_slack_model { TR_SLACK_LINEAR = 0, TR_SLACK_SQUARED = 1 };
enum tr_jacobian_method {
    TR_JAC_FD = 0,     /* forward-difference Jacobian, then Broyden updates; refreshed
                            by finite differences when progress is poor */
    TR_JAC_NEWTON = 1, /* fresh forward-difference Jacobian every iteration */
    TR_JAC_HYBRID = 2  /* GSL's hybridsj (Powell dogleg trust region, scaled, rank-1
                            updates) with the same forward-difference Jacobian */
};
enum tr_control { TR_DISPLACEMENT = 0, TR_TENSION = 1 };

/* Limits of the options and values accepted (tr_options_check, tr_model_alloc); the
 * glue exports them so that the Python layer checks the same ranges.
 * Largest fixed step count: an 8th-order method gains nothing beyond a few thousand
 * steps on [0, L]; the cap keeps max_nfev a bound on the work. */
#define TR_MAX_STEPS 100000
/* Smallest adaptive-integrator tolerance: ~50 ulp; a tighter one cannot be met in
 * double precision and only shrinks the step to underflow. */
#define TR_RTOL_MIN 1e-14
/* Caps of the iteration, evaluation and continuation counts and of the node count. */
#define TR_MAX_ITER_CAP         1000000
#define TR_MAX_NFEV_CAP         1000000000
#define TR_MAX_CONTINUATION_CAP 1000000
#define TR_MAX_NODES            1000000
/* Work is counted in units of one right-hand-side evaluation of a planar Kirchhoff rod
 * without tendons (~25-30 ns of CPU here); an evaluation of a scene's ODE counts its
 * relative cost (tr_model.rhs_work: a spatial Cosserat rod with three tendons ~9), the
 * dense linear algebra its own (tr_lu_work, tr_trsv_work in tr_internal.h).  The default
 * budget lets a hopeless solve give up after ~1 s whatever the formulation (the same
 * budget for any number of shooting segments; an LU it cannot pay for is not started).
 * Converged solves take 10^2-10^6 units, up to ~1.6e7 where a warm solve lands on an
 * unstable equilibrium and continues from its guess along stable stages (a plain rod
 * stepped from F L^2/EI = 91 to 100 at 2440 RK8 steps: 1.55e7), 3.05e7 for a tendon at
 * 45 deg under a tensile load L sqrt(T/EI) = 30 (8 automatic segments, continuation; the
 * stress suite's costliest success within ~1 s), 8.6e7 for 2.6 kN on a 1.2 mm wire (41
 * segments, 1.6 s: beyond the default, it says so and names max_work). */
#define TR_DEFAULT_MAX_WORK 3.5e7
/* Largest work budget and wall-clock limit accepted. */
#define TR_MAX_WORK_CAP 1e15
#define TR_MAX_TIME_CAP 1e9
/* The caller's poll hook runs at most this often [s] (and the wall clock is read). */
#define TR_POLL_INTERVAL 2e-3
/* Output nodes of a solve by default: a smooth plot of the backbone. */
#define TR_DEFAULT_NODES 101
/* Largest number of shooting segments. */
#define TR_MAX_SHOOTING_SEGMENTS 64
/* Range of the rod's L [m], EI, GJ [N m^2]: the scales EI/L^2, EI/L and the
 * stiffness ratios must stay normal doubles ... */
#define TR_ROD_MIN 1e-100
#define TR_ROD_MAX 1e100
/* ... and of a finite axial or shear rigidity EA, GA [N] of the rod or a tendon's
 * EA [N] (a subnormal EA would make tau/EA overflow). */
#define TR_EA_MIN 1e-100
#define TR_EA_MAX 1e150
/* |sin phi| of a tendon angle below this counts as in the x-z plane (phi = 0 or pi
 * given in floating point): the planarity rule of tr_is_planar. */
#define TR_PLANAR_SIN 1e-12

/* Column layouts of the flat input arrays of tr_model_alloc. */
enum tr_rod_col {
    TR_ROD_L,
    TR_ROD_EI,
    TR_ROD_GJ,
    TR_ROD_EA,
    TR_ROD_GA,
    TR_ROD_KIRCHHOFF,
    TR_ROD_NCOL
};
enum tr_tendon_col {
    TR_TD_OFFSET,     /* b [m] */
    TR_TD_ANGLE,      /* phi [rad] */
    TR_TD_SLOPE,      /* a [-] */
    TR_TD_EA,         /* [N], inf: inextensible */
    TR_TD_END,        /* anchor arc length t [m] */
    TR_TD_CONTROL,    /* TR_DISPLACEMENT (0) or TR_TENSION (1) */
    TR_TD_VALUE,      /* q [m] (> 0 retracts) or tau [N] */
    TR_TD_PRETENSION, /* [N] */
    TR_TD_NCOL
};
enum tr_load_col {
    TR_LD_S,
    TR_LD_F,
    TR_LD_M = 4,
    TR_LD_NCOL = 7
}; /* s [m], F (3) [N], M (3) [N m] */
enum tr_dload_col { TR_DL_S0, TR_DL_S1, TR_DL_F, TR_DL_NCOL = 5 }; /* start, end [m], F (3) [N/m] */
/* Backbone sections (tr_model_alloc_ext): section j spans [end of j - 1 (0 for j = 0),
 * end of j] with its own rigidities and its precurvature u* (body frame, the curvature
 * and twist of its unstressed shape, constant on the section); the last end is L. */
enum tr_section_col {
    TR_SC_END, /* arc length where the section ends [m] */
    TR_SC_EI,  /* [N m^2] */
    TR_SC_GJ,  /* [N m^2] */
    TR_SC_EA,  /* [N] (inf on a Kirchhoff rod) */
    TR_SC_GA,  /* [N] (inf on a Kirchhoff rod) */
    TR_SC_U,   /* precurvature ux, uy, uz [1/m] (3 columns) */
    TR_SC_NCOL = 8
};
/* General tendon routing (tr_model_alloc_ext): rows [tendon index, kind, s0, s1 [m],
 * p (8)].  A tendon without rows runs linearly (offset, angle, slope of its row).
 *   TR_ROUTE_HELIX, one row on [0, end]: the angle turns at p0 = dphi/ds [rad/m],
 *     r(s) = (a s + b)(cos(phi + p0 s), sin(phi + p0 s), 0);
 *   TR_ROUTE_PIECE, rows tiling [0, end] in order: on [s0, s1], with h = s - s0,
 *     r(s) = (p0 + p1 h + p2 h^2 + p3 h^3, p4 + p5 h + p6 h^2 + p7 h^3, 0) [m]
 *     (a cubic spline, or straight pieces between disks); every s0, s1 is a breakpoint. */
enum tr_route_col { TR_RT_TENDON, TR_RT_KIND, TR_RT_S0, TR_RT_S1, TR_RT_P, TR_RT_NCOL = 12 };
enum tr_route_kind { TR_ROUTE_LINEAR = 0, TR_ROUTE_HELIX = 1, TR_ROUTE_PIECE = 2 };
/* Per integration segment: the rigidities and precurvature of the section it lies in. */
enum tr_segrod_col { TR_SR_EI, TR_SR_GJ, TR_SR_EA, TR_SR_GA, TR_SR_U, TR_SR_NCOL = 7 };

typedef struct tr_options {
    int integrator;      /* tr_integrator; default TR_RK8 (3-8 steps reach 1e-8 on a 90 deg bend) */
    int steps;           /* total fixed steps over [0, L]; 0 = automatic (start small, verify by
                             step doubling, refine while the estimate exceeds tol) */
    double rtol;         /* relative/absolute (scaled) tolerance of the adaptive integrator;
                             default 1e-10 (reference solutions) */
    double tol;          /* convergence: scaled residual max-norm; default 1e-10
                             (about 1e-10 relative tip accuracy, far below model error) */
    int max_iter;        /* Newton/Broyden iterations per solve; default 50 */
    int max_nfev;        /* residual evaluations (integrations) in total; default 20000 */
    int jacobian_method; /* tr_jacobian_method; default TR_JAC_FD */
    int slack_model;     /* tr_slack_model; default TR_SLACK_LINEAR (nonsingular at the switch) */
    int continuation;    /* 1: ramp loads and actuation when a solve fails; default 1 */
    int max_continuation;  /* cap on continuation steps; default 64 */
    int force_spatial;     /* 1: solve planar scenes with the spatial formulation; default 0 */
    int tip_only;          /* 1: record the tip state only; default 0 */
    int shooting_segments; /* multiple shooting: number of shooting segments M (interior
                             nodes at j L / M carry full-state unknowns and continuity
                             residuals); default 1 = single shooting.  Needed for tensile
                             axial loads with L sqrt(T/EI) >~ 7 (growth e^(L sqrt(T/EI)/M)) */
    double max_work;       /* work budget per solve [units of one planar right-hand-side
                             evaluation, see TR_DEFAULT_MAX_WORK], everything included
                             (continuation, step verification, confirmation); deterministic,
                             so a solve stays bitwise reproducible; default TR_DEFAULT_MAX_WORK
                             (a hopeless solve gives up within ~1 s) */
    double max_time;       /* wall-clock limit per solve [s], 0: none; default 0.  Opt-in and
                             not deterministic (the machine's speed decides where it stops) */
    int auto_shooting;     /* 1: with shooting_segments = 1, the model chooses multiple
                              shooting where tensile loads make the single-shooting
                              sensitivities grow past exp(TR_AUTO_SHOOT_GROWTH) (tr_options.c) */
    int accept_unstable;   /* 1: a converged unstable equilibrium is a success and the solve
                             judges no stability (tr_stability on request); default 0: every
                             solve judges its answer and never succeeds on an unstable one
                             (tr_branch.c) */
} tr_options;

tr_options tr_default_options(void);
/* TR_OK, or TR_EINVAL with a message naming the first option out of its range. */
int tr_options_check(const tr_options *opt, char *msg, size_t msglen);

/* ----------------------------------------------------------------- model */
typedef struct tr_tendon {
    double b;          /* offset at s = 0 [m] */
    double phi;        /* angle of the routing plane about e3, body frame [rad] */
    double a;          /* slope d(offset)/ds [-] */
    double EA;         /* axial rigidity [N]; INFINITY = inextensible */
    double t;          /* arc length of the anchor, 0 < t <= L [m] */
    int control;       /* TR_DISPLACEMENT or TR_TENSION */
    double value;      /* q [m] (> 0 retracts) or tau [N] */
    double pretension; /* tension held at q = 0 in the unloaded robot [N] */
    double cphi, sphi; /* cos phi, sin phi (planar scenes: exactly +-1, 0) */
    double wref;       /* sqrt(1 + a^2): its path-length rate in the straight robot [-] */
    double rest;       /* unstretched length of the tendon between base and anchor [m] */
    double rest_dev;   /* rest - sref, computed without cancellation [m] */
    double sref;       /* reference path length in the undeformed robot, t sqrt(1 + a^2) [m] */
    int end_bp;        /* index of the breakpoint where it is anchored */
    int gamma_index;   /* index of its tension/slack unknown, -1 if tension-controlled */
    int len_index;     /* slot of its path-length excess (path length minus the reference
                          sref, integrated as |w| - |w_ref| without cancellation) in the
                          shooting state, -1 if none */
    int target_row;    /* -1, or the row of the model's target whose residual takes the place
                          of this displacement-controlled tendon's length constraint (its
                          displacement then follows from the solution; tr_model_set_target) */
    int route;         /* tr_route_kind of its path */
    double twist;      /* TR_ROUTE_HELIX: dphi/ds [rad/m] */
    double t0[3];      /* unit tangent at s = 0 of the unstressed robot, body frame */
    double rt0[3];     /* r(0) x t0, body frame [m] */
    double mu;         /* Coulomb friction coefficient with its channel [-] (0: frictionless) */
    int slide;         /* the direction it slides in its channel: +1 in (toward the actuator,
                          tension falls along s), -1 out (tension rises along s) */
    int fric_index;    /* slot of its tension deficit tau(0) - tau(s) [N] among the friction
                          states, -1 if frictionless (tr_model_set_friction) */
} tr_tendon;

typedef struct tr_model {
    double L, EI, GJ, EA, GA; /* length [m]; bending, torsional [N m^2]; axial, shear [N] */
    int kirchhoff;            /* 1: v = e3 (unshearable, inextensible backbone) */
    int planar;               /* 1: solved with the planar x-z formulation */
    int nt;                   /* number of tendons */
    tr_tendon *tendon;        /* (nt) */
    int nl;                   /* number of point loads */
    double *load;             /* (nl x 7) [s, F (3) world N, M (3) world N m] as given */
    double dist[3];           /* uniform distributed force, world [N/m] */
    int has_dist;             /* 1 if dist != 0 */
    int nd;                   /* number of partial distributed loads */
    double *dload;            /* (nd x 5) [s0, s1 [m], f (3) world N/m] as given: f on [s0, s1] */
    double *seg_pdist;        /* (nseg x 3) sum of the partial distributed forces on each
                                   segment, world [N/m] (breakpoints at every s0, s1) */
    int has_pdist;            /* 1 if some partial distributed force != 0 */
    int nseg;                 /* number of integration segments */
    double *bp;               /* (nseg + 1) breakpoints, bp[0] = 0, bp[nseg] = L [m] */
    double *bpF, *bpM;        /* (nseg + 1) x 3 point force [N] / moment [N m] sums at each
                                   breakpoint, world frame (bp 0: carried by the base, unused) */
    int *seg_act_start;       /* (nseg + 1) CSR offsets into seg_act */
    int *seg_act;             /* tendons active on each segment (t_i > bp[k]) */
    int ndisp;                /* displacement-controlled tendons (= gamma unknowns) */
    int nshoot;               /* shooting segments M (1: single shooting) */
    double shoot_growth;      /* the exponent int sqrt(T/EI) ds of the tensile loads' growth of
                                 the shooting sensitivities (0: none) */
    int shoot_auto;           /* 1: nshoot was chosen from shoot_growth (Options.auto_shooting) */
    int *bp_node;     /* (nseg + 1) shooting-node index 1..M-1 of each breakpoint, 0 if none */
    int *bp_jump;     /* (nseg + 1) 1 if a load or an anchor sits at the breakpoint */
    int n_unknowns;   /* shooting unknowns: 6 (3 planar) + ndisp + (M - 1) n_states */
    int n_base;       /* base states: 18 spatial (p, R, n_b, m_b), 6 planar */
    int n_states;     /* shooting states: n_base + ndisp path lengths + nfric deficits */
    int n_states_rec; /* recording states: n_base + nt path lengths + nfric deficits + nfric
                         rest lengths */
    int n_stretch;    /* displacement-controlled tendons with finite EA */
    int nfric;        /* tendons with channel friction (mu > 0): one state each, after the
                         path lengths, in both layouts; the recording layout then has one
                         more each, the tendon's rest length from the base */
    double F_s, M_s, tau_s;   /* scales: force EI/L^2 [N], moment EI/L [N m],
                                   tension EI/(r_max L) [N] */
    double len_s;             /* scale of slack and length residuals: r_max (L if 0) [m] */
    double xstate_scale[18];  /* absolute scale of each base state (adaptive control) */
    double rhs_work;          /* cost of one right-hand-side evaluation [work units, see
                                TR_DEFAULT_MAX_WORK], from the formulation */
    int scene_status;         /* 0, or why this (well-formed) scene has no unique solution:
                                   TR_EINDETERMINATE, TR_ENOEQUILIBRIUM, TR_EPRETENSION;
                                   tr_solve then fails at once with scene_message */
    char scene_message[512];  /* the message for scene_status */
    int nsec;                 /* backbone sections given (0: one uniform straight section, the
                                rod row; the rod row's values are the scales either way) */
    double *sec;              /* (nsec x TR_SC_NCOL) the sections as given */
    double *seg_rod;          /* (nseg x TR_SR_NCOL) rigidities and precurvature of each
                                integration segment (section ends are breakpoints) */
    int precurved;            /* 1 if some section has a nonzero precurvature */
    int general;              /* 1 with sections or general routing: the right-hand side reads
                                seg_rod and the routes (0: rod_k and linear tendons) */
    double rod_k[TR_SR_NCOL]; /* EI, GJ, EA, GA of the rod row and u* = 0 */
    int nroute;               /* routing rows given */
    double *route;            /* (nroute x TR_RT_NCOL) as given */
    int *seg_piece;           /* (nseg x nt) the routing row of tendon i on segment k, -1 if
                                none (linear tendons); NULL without general routing */
    int n_routed;             /* tendons with a general (helical, piecewise) path */
    int target_kind;          /* TR_TARGET_NONE, or the tip target whose rows replace the length
                                constraints of the tendons with target_row >= 0 */
    double target[9];         /* angle: theta [rad]; position: p (3) world [m]; direction: the
                                unit tip tangent (3) world and a unit basis b1 (3), b2 (3) of
                                the plane normal to it */
    int view;                 /* 0: a compiled model; 1: a workspace's inputs (tr_data.in): the
                                values its solves use over the compiled model's structure */
} tr_model;

/* Compile a scene.  rod = [L, EI, GJ, EA, GA, kirchhoff]; tendons (nt x 8) rows
 * [b, phi, a, EA, t, control, value, pretension]; loads (nl x 7) rows
 * [s, Fx, Fy, Fz, Mx, My, Mz]; dist (3).  On invalid input returns TR_EINVAL (or
 * TR_ENOMEM), *out = NULL, and a message in msg (msglen bytes).  A well-formed
 * scene without a unique equilibrium (statically indeterminate tendons, no
 * equilibrium, meaningless pretension) compiles, with m->scene_status set. */
int tr_model_alloc(tr_model **out, const double rod[6], const double *tendons, int nt,
                   const double *loads, int nl, const double dist[3], const tr_options *opt,
                   char *msg, size_t msglen);
/* tr_model_alloc with nd partial distributed loads dloads (nd x 5) rows
 * [s0, s1, fx, fy, fz]: the force per length f [N/m], world frame, on [s0, s1]
 * (0 <= s0 < s1 <= L), beside the uniform dist; s0 and s1 become breakpoints.
 * tr_model_alloc is this with nd = 0. */
int tr_model_alloc_dist(tr_model **out, const double rod[6], const double *tendons, int nt,
                        const double *loads, int nl, const double dist[3], const double *dloads,
                        int nd, const tr_options *opt, char *msg, size_t msglen);
/* tr_model_alloc_dist with nsec backbone sections (nsec x TR_SC_NCOL rows, ends increasing,
 * the last at L; NULL / 0: the uniform straight rod of the rod row) and nroute routing rows
 * (nroute x TR_RT_NCOL; NULL / 0: every tendon linear).  Each section end and routing knot
 * is a breakpoint.  The rod row still sets L, the Kirchhoff flag and the scales (EI/L^2,
 * EI/L).  A helical or piecewise tendon makes the scene spatial. */
int tr_model_alloc_ext(tr_model **out, const double rod[6], const double *tendons, int nt,
                       const double *loads, int nl, const double dist[3], const double *dloads,
                       int nd, const double *sections, int nsec, const double *routes, int nroute,
                       const tr_options *opt, char *msg, size_t msglen);
/* 1 when the sections (as for tr_model_alloc_ext) keep a planar scene planar: no
 * precurvature ux or uz. */
int tr_sections_planar(const double *sections, int nsec);
void tr_model_free(tr_model *m);
/* A deep copy of m (NULL when out of memory). */
tr_model *tr_model_clone(const tr_model *m);
/* Deprecated (kept for one release): the tr_data_set_* setters set a workspace's values.
 * These set a model's defaults, which workspaces allocated afterwards start from; call
 * them before any workspace of the model exists.
 * Set the values of a compiled model without changing its structure: value (nt) the
 * actuation value of every tendon (q [m] or tau [N] per its control mode), load
 * (nl x 6) [F (3) N, M (3) N m] world frame of every point load (positions stay),
 * dist (3) the distributed force [N/m], world frame; NULL keeps what the model has.
 * The scene check that depends on values (opposing inextensible tendons on a
 * Kirchhoff backbone) is redone.  TR_EINVAL with a message when a value is not
 * finite, a tension is negative, or a planar model would get an out-of-plane load;
 * the model is then unchanged. */
int tr_model_set_values(tr_model *m, const double *value, const double *load, const double *dist,
                        char *msg, size_t msglen);
/* Deprecated as tr_model_set_values (tr_data_set_pretension).  Set the tendons'
 * pretensions (nt) [N] of a compiled model: the rest lengths are
 * recomputed and the scene checks redone (m->scene_status).  TR_EINVAL with a message
 * when a value is not finite or negative; the model is then unchanged. */
int tr_model_set_pretension(tr_model *m, const double *pretension, char *msg, size_t msglen);
/* Friction between the tendons and their channels (docs/model.md, Section 3): mu (nt)
 * Coulomb coefficients [-] (>= 0, finite) and sliding (nt) the direction each tendon slides
 * in its channel, +1 in (toward the actuator) or -1 out (toward the anchor).  Each tendon
 * with mu > 0 carries its tension along s as a state (its deficit tau(0) - tau(s)), so
 * this changes the problem's structure: call it right after compiling, before any
 * workspace of the model is allocated.  All mu = 0 leaves the model exactly as compiled.
 * TR_EINVAL with a message (the model unchanged) for a value out of range. */
int tr_model_set_friction(tr_model *m, const double *mu, const int *sliding, char *msg,
                          size_t msglen);
/* Inverse actuation inside the shooting system: the kinds of tip target. */
enum tr_target_kind {
    TR_TARGET_NONE = 0,
    TR_TARGET_ANGLE = 1,     /* planar: the tip angle theta [rad] (unwrapped), 1 component */
    TR_TARGET_DIRECTION = 2, /* spatial: the tip tangent (3, normalised), 2 components */
    TR_TARGET_POSITION = 3   /* spatial: the tip position (3) world [m], 3 components */
};
/* Replace the length constraints of the n displacement-controlled tendons `tendons` by
 * the residuals of a tip target (values: theta, or 3 numbers), one component each (n
 * must be the target's component count); TR_TARGET_NONE restores every constraint.
 * Their prescribed displacements then only start the solve; tr_solve reports the
 * displacements the solution needs.  TR_EINVAL with a message for a kind this
 * formulation lacks, a wrong count, a tendon that is not displacement-controlled, or
 * values that are not finite; the model is then unchanged.  Deprecated as
 * tr_model_set_values: tr_data_set_target sets a workspace's target. */
int tr_model_set_target(tr_model *m, int kind, const double *values, const int *tendons, int n,
                        char *msg, size_t msglen);
/* 1 when a scene of these flat arrays (as for tr_model_alloc) lies in the x-z plane:
 * every tendon at |sin phi| <= TR_PLANAR_SIN, no load with Fy, Mx or Mz, dist_y = 0. */
int tr_is_planar(const double *tendons, int nt, const double *loads, int nl, const double dist[3]);
/* tr_is_planar with partial distributed loads (nd x 5, as for tr_model_alloc_dist): each
 * with f_y = 0 too. */
int tr_is_planar_dist(const double *tendons, int nt, const double *loads, int nl,
                      const double dist[3], const double *dloads, int nd);

/* ------------------------------------------------------------------ data */
#define TR_MSGLEN 1024

/* The workspace of a model's solves (tr_data_alloc): opaque; what a caller reads of it is
 * read through the accessors below (tr_data_result, tr_data_outputs, ...). */
typedef struct tr_data tr_data;

/* Allocate a workspace.  nodes: if node_s is NULL, nnode uniform nodes over
 * [0, L] plus every interior load/anchor breakpoint twice (state before and after
 * the jump) and every other interior breakpoint (shooting node) once;
 * otherwise the nnode sorted arc lengths node_s.  tip_only (opt) records only
 * the tip.  Returns NULL on failure (msg says why). */
tr_data *tr_data_alloc(const tr_model *m, const tr_options *opt, int nnode, const double *node_s,
                       char *msg, size_t msglen);
/* tr_data_alloc with flags, for a workspace that serves many solves (a controller, a batch,
 * a Problem): with TR_ALLOC_ALL nothing the core does allocates until tr_data_free.
 * tr_data_alloc (no flag) allocates every buffer of a solve but the nested workspaces
 * below, which the first solve that needs them allocates and the workspace keeps: a
 * workspace allocated per solve (Python's tr.solve) pays only for what it uses.
 *   TR_ALLOC_GRIDS: the stability test's grid workspaces for its first grids (unless
 *     accept_unstable); a verdict that refines beyond them allocates a finer one;
 *   TR_ALLOC_FINEST: the same with room for the finest grid the test refines to
 *     (TR_STAB_MAX_ELEMENTS elements, Cosserat: two grids of ~800 nodes, ~2 MB each);
 *   TR_ALLOC_CONFIRM: the confirmation's second formulation (the scene compiled with 8 or
 *     2 M shooting segments, and its workspace), used on a rare path (continuation
 *     stalled, a direct solve converged off the load path);
 *   TR_ALLOC_CALLS: room for the buffers of tr_path and tr_actuate (tr_path.h,
 *     tr_actuate.h) on this workspace, sized for the largest call of the model (a path:
 *     its (k + 1)-square bordered system; an actuation: every tendon a control, a target
 *     of 6 components); without it each call allocates its own and frees them.
 * Measured on a Python tr.solve warm from a guess (no verdict needed): GRIDS +25 us,
 * FINEST +160 us, FINEST | CONFIRM ~ +300 us.  The LU factorisations are the core's own
 * (GSL >= 2.7's allocated a pivot vector per call), so GSL allocates nothing either. */
enum {
    TR_ALLOC_GRIDS = 1,
    TR_ALLOC_FINEST = 2,
    TR_ALLOC_CONFIRM = 4,
    TR_ALLOC_CALLS = 8,
    TR_ALLOC_ALL = 15
};
tr_data *tr_data_alloc_ext(const tr_model *m, const tr_options *opt, int nnode,
                           const double *node_s, int flags, char *msg, size_t msglen);
void tr_data_free(tr_data *d);

/* ---------------------------------------------------------------- inputs */
/* The values a workspace's solves use (MuJoCo's mjData inputs): a compiled model is never
 * written after compilation (tr_model_set_friction belongs to compilation), so one model
 * serves any number of workspaces and threads read-only.  tr_data_alloc copies the
 * values the model was compiled with (the defaults); these set them per workspace, with
 * the same meaning and checks as the tr_model_set_* functions below (TR_EINVAL with a
 * message, the workspace then unchanged; also when d is not m's workspace).  Values that
 * enter precomputed data are redone in the workspace, each at the cost of its own size:
 * point loads -> their sums at the breakpoints (O(nl + nseg)); pretensions -> the rest
 * lengths and the scene checks (O(nt^2)); actuation values -> the indeterminacy check
 * (O(nt^2)).  A linearisation's or a path's design parameter (rigidities, a tendon's EA,
 * offset, slope, friction) -> the per-segment rigidities and the tendon's frame and rest
 * lengths, on copies the workspace holds (O(nseg + nt)); the model's arrays are shared
 * by every workspace, never copied per workspace but the values' own. */
int tr_data_set_values(const tr_model *m, tr_data *d, const double *value, const double *load,
                       const double *dist, char *msg, size_t msglen);
int tr_data_set_pretension(const tr_model *m, tr_data *d, const double *pretension, char *msg,
                           size_t msglen);
int tr_data_set_target(const tr_model *m, tr_data *d, int kind, const double *values,
                       const int *tendons, int n, char *msg, size_t msglen);
/* The model's own values (those it was compiled with) again. */
void tr_data_reset_inputs(const tr_model *m, tr_data *d);

/* ---------------------------------------------------------------- solver */
/* Set the unknowns from a physical guess (6 + 2 nt: n(0) world, m(0) world,
 * tension, slack; NULL: the straight robot), take a scaled Jacobian (k x k) to
 * reuse if jac != NULL, and evaluate the residual. */
int tr_solve_init(const tr_model *m, tr_data *d, const double *guess, const double *jac);
/* One damped Newton/Broyden iteration with backtracking.  Returns TR_CONTINUE,
 * or a negative status. */
int tr_solve_iterate(const tr_model *m, tr_data *d);
/* TR_OK when the scaled residual max-norm <= tol, or <= the residual's round-off floor
 * (the unit round-off times the largest internal force and moment the residual sums, in
 * EI/L^2 and EI/L: a smaller residual cannot be told from zero), else TR_CONTINUE.  A
 * solve that converges above tol by the floor ends TR_ROUNDOFF. */
int tr_solve_test(const tr_model *m, const tr_data *d);
/* One-call driver: init, iterate, continuation on failure, confirmation of an
 * equilibrium found off the load path, step verification (steps = 0), conditioning
 * check, diagnosis of a failure, recording pass.  Returns d->status. */
int tr_solve(const tr_model *m, tr_data *d, const double *guess, const double *jac);
/* What a solve's step verification measured (steps = 0, fixed-step integrators): the
 * verified step count, the truncation estimate there (scaled) and the scaled unknowns
 * (k) it was measured at.  A later solve of the same model structure that starts from
 * that solution starts at this step count, and skips the verification when it ends
 * close enough to x (tr_verify_carried). */
typedef struct {
    int steps;
    double estimate;
    const double *x;
    const double *values; /* (nt) the tendons' actuation values (q [m] / tau [N]) of the scene
                             it was measured on; NULL: not known, and then a model with a
                             tension-controlled tendon verifies afresh (its tensions move the
                             state without moving the unknowns) */
} tr_verified;
/* tr_solve from a guess that came with its verification record v (NULL: none; the
 * automatic step count starts from v->steps). */
int tr_solve_from(const tr_model *m, tr_data *d, const double *guess, const double *jac,
                  const tr_verified *v);
/* The same, warm from the last successful solve in this workspace (its unknowns,
 * Jacobian and verified step count, kept in the workspace); cold if there is none.
 * The workspace's values may have changed since (tr_data_set_values). */
int tr_solve_warm(const tr_model *m, tr_data *d);
/* Forget the last successful solve (the next tr_solve_warm starts cold). */
void tr_forget(tr_data *d);
/* A hook the solve calls about every TR_POLL_INTERVAL of wall time (at most), from the
 * thread that runs it; a nonzero return stops the solve promptly with TR_EINTERRUPTED.
 * The interval runs across solves, so a loop of solves each shorter than it reaches the
 * hook too.
 * NULL: none.  The workspace stays usable after an interrupted solve. */
void tr_set_poll(tr_data *d, int (*poll)(void *ctx), void *ctx);
/* Recording pass at the current unknowns: fills s, pos, rot, force, moment,
 * tension, slack, displacement. */
int tr_record(const tr_model *m, tr_data *d);
/* Recording pass from given scaled unknowns x (k) at a given step count (a solution's
 * formulation.steps): the states of that solution at this workspace's nodes, without
 * solving again. */
int tr_record_from(const tr_model *m, tr_data *d, const double *x, int steps);
/* The state of a solution with scaled unknowns x (k) at a step count, set in the workspace
 * without solving (what tr_record_from records, tr_linearize linearises): TR_OK, TR_EINVAL
 * (another model's workspace, steps out of range), TR_ENONFINITE (x not finite). */
int tr_state_from(const tr_model *m, tr_data *d, const double *x, int steps);
/* Scaled residual at x (k) with the current step count; f (k). */
int tr_residual(const tr_model *m, tr_data *d, const double *x, double *f);
/* Compliance (6 x 6, row-major): [dx (3), dtheta (3)] per [F (3), M (3)] applied at
 * the breakpoint s_probe (which must be a load position of the model or L), world
 * frame, linearised at the solution (call tr_solve first): tr_linearize with the six
 * probe loads at s_probe. */
int tr_compliance(const tr_model *m, tr_data *d, double s_probe, double C[36]);

/* ---------------------------------------------------------- linearisation */
/* What a parameter of tr_linearize is. */
enum tr_param_kind {
    TR_PAR_VALUE,     /* tendon `index`'s actuation value: q [m] (displacement-controlled) or
                         tau [N] (tension-controlled) */
    TR_PAR_LOAD,      /* a probe load at breakpoint index / 6 (1..nseg), component index % 6 of
                         [F (3) N, M (3) N m], world frame (spatial formulation only) */
    TR_PAR_ROD_EI,    /* the rod's EI [N m^2] */
    TR_PAR_ROD_GJ,    /* the rod's GJ [N m^2] */
    TR_PAR_ROD_EA,    /* the rod's EA [N] (Cosserat rods only) */
    TR_PAR_ROD_GA,    /* the rod's GA [N] (Cosserat rods only) */
    TR_PAR_TENDON_EA, /* tendon `index`'s EA [N] (finite) */
    TR_PAR_OFFSET,    /* tendon `index`'s offset b [m] (not for a pretensioned set) */
    TR_PAR_SLOPE,     /* tendon `index`'s slope a [-] (not for a pretensioned set) */
    TR_PAR_FRICTION,  /* tendon `index`'s friction coefficient mu [-] (a tendon compiled with
                         friction, mu > 0; a central difference of it stays above 0) */
    TR_PAR_NKIND
};
typedef struct {
    int kind;  /* tr_param_kind */
    int index; /* tendon index, load slot (6 b + component), unused for the rod */
} tr_param;

/* The linearisation of a solved scene (call tr_solve first; its unknowns d->x are the
 * state) with respect to np parameters, by the implicit function theorem on the
 * shooting map: differences (`scheme`: TR_DIFF_CENTRAL, 2k evaluations, truncation ~1e-11;
 * TR_DIFF_FORWARD, k evaluations, ~1e-8) give the Jacobian of the residual and of the poses
 * at the breakpoints with respect to the unknowns; each parameter's effect on the
 * residual and the poses (two more evaluations, none for a prescribed displacement or a
 * probe load at the tip) then moves the unknowns by a linear solve.  No nonlinear solve.
 *   rows (nrow): breakpoint indices 1..nseg whose pose derivatives are reported;
 *   dpose (np x nrow x 6): [dx (3) world [m], dtheta (3) world rotation-vector increment
 *     [rad]] at each row's breakpoint per unit of parameter j;
 *   dtension (np x nt) or NULL: each tendon's tension change [N] per unit of parameter j;
 *   dslack (np x nt) or NULL: each tendon's slack change [m] per unit of parameter j (nonzero
 *     only for a slack displacement-controlled tendon, or one given its slack side);
 *   at_switch (nt) or NULL: on entry, the side wanted for a displacement-controlled tendon
 *     within the difference stencil of its switch (+1 taut, -1 slack, 0 the side it is on;
 *     others ignore it); on return, the side of its taut/slack switch whose derivatives
 *     each tendon was given (a tension-controlled one: at tension 0): +1 the taut side, -1
 *     the slack side, 0 not at the switch.  Unless asked otherwise, the side it is on, the
 *     taut one when exactly at the switch; where the taut side leaves the Jacobian singular
 *     (indeterminate tensions), the slack one.
 * TR_OK; TR_EINVAL (a parameter this model does not have, or a probe load on a planar
 * model; message set); TR_ESINGULAR; TR_EBUDGET / TR_EINTERRUPTED; an integration
 * failure.  The workspace's unknowns stay those of the solution; its Jacobian d->J
 * becomes the central-difference one. */
enum tr_diff_scheme { TR_DIFF_CENTRAL = 0, TR_DIFF_FORWARD = 1 };
int tr_linearize(const tr_model *m, tr_data *d, const tr_param *par, int np, const int *rows,
                 int nrow, double *dpose, double *dtension, double *dslack, int *at_switch,
                 int scheme);

/* The message of a converged solve (nit iterations, final scaled residual): the one
 * wording of a success, for entry points that store no message per converged point. */
void tr_message_converged(char *msg, size_t len, int nit, double residual, double tol);

/* The physical guess of the current unknowns (after tr_solve: of the solution):
 * g (6 + 2 nt) = [n(0) world (3) [N], m(0) world (3) [N m], tension (nt) [N],
 * slack (nt) [m]], n(0), m(0) the backbone's internal force and moment at the base.
 * The exact inverse of the map tr_solve applies to a guess. */
void tr_base_state(const tr_model *m, const tr_data *d, double *g);

/* Lean warm solve at a fixed step count (opt.steps > 0, fixed-step integrator): from
 * the scaled unknowns x0 (k) with the Jacobian jac (k x k; NULL: the workspace's own),
 * full Newton steps, each of which must reduce the residual's max-norm, good Broyden
 * updates guarded against round-off; no line search, continuation, step verification,
 * polish or recording (tr_record or tr_record_tip follow).  At most max_iter
 * iterations.  TR_OK, or < 0 when the caller should run tr_solve instead. */
int tr_solve_lean(const tr_model *m, tr_data *d, const double *x0, const double *jac, int max_iter);
/* The stability verdict of the current unknowns (a solution): d->stable, d->stability,
 * d->stab_index, d->stab_reason (bench/results/stability_design.md). */
void tr_stability(const tr_model *m, tr_data *d);
/* The same verdict, first by a coarse test that decides without the margin (d->stability
 * NaN) when no eigenvalue is near zero, else by tr_stability. */
void tr_stability_quick(const tr_model *m, tr_data *d);
/* The same for the solution with scaled unknowns x (k) at a step count (a solution's
 * formulation.steps), as tr_record_from does for its states (quick: tr_stability_quick).
 * TR_EINVAL when steps is out of range or the workspace is another model's. */
int tr_stability_of(const tr_model *m, tr_data *d, const double *x, int steps, int quick);
/* The verdict record a warm solve may keep instead of judging again (tr_branch.c), flat:
 * its length for this model; a copy of the workspace's (1, or 0 when it has none); and
 * one set into a workspace, e.g. from the solution a guess came from (a record of another
 * length or with values out of range is refused: -1). */
int tr_carry_len(const tr_model *m, const tr_data *d);
int tr_carry_get(const tr_model *m, const tr_data *d, double *rec);
int tr_carry_set(const tr_model *m, tr_data *d, const double *rec, int len, const char *reason);
/* The tip state of the current unknowns into d->tip, with the tensions, slacks and
 * the displacement of displacement-controlled tendons (NaN for tension-controlled ones,
 * which only the recording pass integrates): from the last shooting evaluation if it
 * was at these unknowns, else one more evaluation. */
int tr_tip_state(const tr_model *m, tr_data *d);
/* tr_tip_state, and the tip node of a tip-only workspace filled from it (no recording
 * pass), e.g. after tr_solve_lean. */
int tr_record_tip(const tr_model *m, tr_data *d);

/* ------------------------------------------------------- reading a workspace */
/* What the last solve did: its status, counts and measures, and its message. */
typedef struct tr_result {
    int status;           /* d's status (tr_solve's return) */
    int nit, nfev, njev;  /* iterations, residual evaluations, Jacobians */
    int cont_steps;       /* continuation stages */
    int steps;            /* the step count it ended at (fixed-step integrators) */
    int ver_carried;      /* 1: that step count was vouched for by the guess's verification */
    double work;          /* work spent [units, see TR_DEFAULT_MAX_WORK] */
    double residual_norm; /* final scaled residual max-norm */
    double jacobian_cond; /* 1-norm condition number of the final Jacobian (NaN: none) */
    double truncation;    /* step-doubling estimate (scaled residual), NaN if not estimated */
    const char *message;  /* what happened and what to do about it (the workspace's) */
} tr_result;
void tr_data_result(const tr_data *d, tr_result *r);
/* The state of the last solve or recording, pointers into the workspace (valid until its
 * next call): nodes and the states there, the tendons' tensions, slacks and displacements,
 * the tip, the scaled unknowns and the Jacobian. */
typedef struct tr_outputs {
    int nnode;                  /* output nodes (1 when tip_only) */
    int k;                      /* unknowns */
    int lazy;                   /* 1: the node arrays were not filled (tr_data_set_lazy) */
    const double *s;            /* (nnode) arc length [m] */
    const double *pos;          /* (nnode x 3) position, world [m] */
    const double *rot;          /* (nnode x 9) rotation body-to-world, row-major */
    const double *force;        /* (nnode x 3) internal force, world [N] */
    const double *moment;       /* (nnode x 3) internal moment, world [N m] */
    const double *node_tension; /* (nnode x nt) each tendon's tension at each node [N] */
    const double *node_rest;    /* (nnode x nt) a frictional tendon's rest length from the base
                                 to each node [m]; NaN for the others */
    const double *tension;      /* (nt) tension at the actuator [N] */
    const double *slack;        /* (nt) slack [m] */
    const double *displacement; /* (nt) actuator displacement [m] */
    const double *tip;          /* (18) p (3) world [m], R (9) row-major, force (3) [N], moment
                                 (3) [N m] world */
    double tip_angle;           /* planar: the tip tangent's angle from +z toward +x [rad],
                                 unwrapped; spatial: NaN */
    const double *x;            /* (k) scaled unknowns */
    const double *J;            /* (k x k) scaled Jacobian, row-major */
} tr_outputs;
void tr_data_outputs(const tr_data *d, tr_outputs *o);
/* The stability verdict of the last solve (tr_stability, or judged by tr_solve): stable
 * 1 / 0 / -1 (not tested, or critical within the test's accuracy: reason says which), the
 * margin [EI/L] (NaN: not computed), the number of negative modes, the reason. */
typedef struct tr_verdict {
    int stable, index;
    double margin;
    const char *reason;
} tr_verdict;
void tr_data_verdict(const tr_data *d, tr_verdict *v);
/* The step verification that vouches for the current step count (as tr_verified, its
 * pointers into the workspace): 1 and v filled, or 0 when there is none. */
int tr_data_verified(const tr_data *d, tr_verified *v);
/* The reason of the verdict record a warm solve may keep (tr_carry_get), or NULL when the
 * workspace has none. */
const char *tr_data_carry_reason(const tr_data *d);
/* The options of the workspace, its message, whether it holds a successful solve for
 * tr_solve_warm; and the lazy flag: 1, a solve fills the tip, tensions and slacks only (and
 * the displacement of displacement-controlled tendons; NaN for the others), the node arrays
 * stay untouched until tr_record_from. */
const tr_options *tr_data_options(const tr_data *d);
const char *tr_data_message(const tr_data *d);
int tr_data_has_last(const tr_data *d);
void tr_data_set_lazy(tr_data *d, int lazy);
/* 1: a converged solve takes one more Newton step whatever its size (kept unless it raises
 * the residual), so that a change of the values too small to lift the residual above tol
 * still moves the state. */
void tr_data_set_polish_once(tr_data *d, int polish_once);

#ifdef __cplusplus
}
#endif
#endif /* TENDONROD_H */
