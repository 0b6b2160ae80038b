/*
 * tr_dyn.h -- the rod/tendon dynamics in time (tr_dyn.c): an implicit time step
 * (BDF-alpha: alpha = -1/2 the trapezoidal rule, 0 BDF2) turns each step into a
 * boundary-value problem in s, solved by the shooting core (tr_solve_lean, warm from the
 * step before, its Jacobian Broyden-updated across steps, a fresh difference Jacobian
 * only where a step does not converge with it).  Spatial Cosserat formulation, fixed-step
 * RK4 in s: every step integrates over the same grid, whose stage points keep the
 * history (tr_dyn_ctx, tr_internal.h).  docs/guide/dynamics.md states the design.
 */
#ifndef TR_DYN_H
#define TR_DYN_H

#include "tendonrod.h"

/* The smallest step fraction of a time step's backtracking Newton fallback: 2^-10, where
 * the residual's decrease is below round-off for a Jacobian that is not a descent
 * direction. */
#define TR_DYN_MIN_LAMBDA (1.0 / 1024.0)

/* A time step's shooting problem: the inertia rho A c0^2 (c0 the scheme's coefficient of
 * y in y_t, 1.5 / dt for BDF2) acts on the bending like an elastic foundation, whose
 * solutions in s grow like exp(s (rho A c0^2 / (4 EI))^(1/4)).  One shooting segment up
 * to an exponent of TR_DYN_SHOOT_ONE, above it segments of at most TR_DYN_SHOOT_PER each.
 * Measured: single shooting converges every step up to 15.1 on Till's tendon robot (BDF2,
 * 20 RK4 steps; fails at 17.1) and 17.6 on a 0.2 m, 2 mm cantilever (40 steps; fails at
 * 19.7); with several segments the cantilever's first step has a singular Jacobian from
 * 9.3 per segment on (3 segments, the trapezoidal rule; 11.4 with 2) and converges at
 * 6.0-8.0 per segment (2-4 segments), Till's robot at 5.7-12.1. */
#define TR_DYN_SHOOT_ONE 14.0
#define TR_DYN_SHOOT_PER 8.0
/* A run whose step fails with M segments chosen from the growth is redone with 2M while
 * each of the 2M segments still carries a growth of at least TR_DYN_SHOOT_RETRY_PER:
 * below it a segment amplifies an error by at most exp(2) ~ 7, the shooting Jacobian is
 * no longer what fails, and more segments only add unknowns (k^3 Newton work). */
#define TR_DYN_SHOOT_RETRY_PER 2.0

/* What a run integrates: nsteps steps of dt from the solution x0 (scaled unknowns). */
typedef struct tr_dyn_spec {
    int nsteps;           /* steps of the run (>= 1) */
    double dt;            /* time step [s] (> 0) */
    double alpha;         /* BDF-alpha parameter in [-1/2, 0] */
    double rhoA;          /* mass per length [kg/m] (> 0) */
    double rhoJ[3];       /* rotary inertia per length about the body axes [kg m] (>= 0) */
    double eta;           /* Kelvin-Voigt retardation time [s] (>= 0) */
    double drag;          /* air drag per body-frame component [N s^2/m^3] (>= 0) */
    const double *values; /* ((nsteps + 1) x nt) actuation per time: q [m] or tau [N] */
    const double *loads;  /* ((nsteps + 1) x nl x 6) point loads per time, world, or NULL */
    const double *dist0;  /* (3) the start's distributed load [N/m], base frame, where it
                             differs from the model's (which acts from step 1 on), or NULL;
                             row 0 of values and loads is likewise the start's */
    int max_iter;         /* Newton iterations per step before a fresh Jacobian (>= 1) */
    const double *resume; /* (tr_dyn_state_len) a previous run's final state (out->state) to
                             go on from, with the same model, grid and dt (x0 then unused),
                             or NULL: start from the solution x0 at rest */
} tr_dyn_spec;

/* Columns of tr_dyn_out.energy. */
#define TR_DYN_NE 6

/* What it returns: rows 0 .. done of caller-allocated arrays of nsteps + 1 rows. */
typedef struct tr_dyn_out {
    double *tip;      /* (rows x 12) tip position (3) world [m], rotation (9) row-major */
    double *tension;  /* (rows x nt) [N] */
    double *slack;    /* (rows x nt) [m] */
    double *energy;   /* (rows x TR_DYN_NE) kinetic, elastic (rod strain), potential of the
                         distributed loads, dissipated since the start, the
                         displacement-held tendons' strain energy, their motors' work since
                         the start [J] */
    double *residual; /* (rows) scaled residual max-norm of each step */
    int *iters;       /* (rows) Newton iterations of each step */
    double *backbone; /* (rows x nb x 3) positions at the RK4 grid's nodes, or NULL */
    double *s;        /* (nb) the nodes' arc lengths [m] (tr_dyn_nodes), or NULL */
    double *state;    /* (tr_dyn_state_len) the last good step's state (history, unknowns,
                         dissipation), to resume from, or NULL */
    int done;         /* the last step completed (0: none) */
    int nit, nfev, njev;
    char message[512];
} tr_dyn_out;

/* The length of a run's state (tr_dyn_out.state, tr_dyn_spec.resume): the history at every
 * stage point of the last two steps and its time derivative, the last two unknowns, the
 * dissipated power and energy, dt, the motors' work and the last tensions.  Call after the workspace's steps are set (opt.steps). */
int tr_dyn_state_len(const tr_model *m, tr_data *d);
/* Backbone nodes of a run's workspace (the RK4 grid's step starts and the tip), at its
 * options' step count. */
int tr_dyn_nodes(const tr_model *m, tr_data *d);
/* The exponent of a step's shooting growth over the rod at mass rhoA [kg/m], time step dt
 * [s] and BDF-alpha alpha (the foundation's, integrated over the segments' EI, plus the
 * tensile loads' of tr_shooting_growth), and the shooting segments it takes (1 up to
 * TR_DYN_SHOOT_ONE, else TR_DYN_SHOOT_PER each; at most TR_MAX_SHOOTING_SEGMENTS). */
double tr_dyn_growth(const tr_model *m, double rhoA, double dt, double alpha);
int tr_dyn_segments(const tr_model *m, double rhoA, double dt, double alpha);
/* The segments to redo a run with after it ended with status st on m's segments (chosen
 * from the growth, not fixed by the caller): twice m->nshoot where st is a failed step
 * (not TR_OK, TR_EINVAL, TR_ENOMEM, TR_EBUDGET, TR_EINTERRUPTED), the count is at most
 * TR_MAX_SHOOTING_SEGMENTS and each segment keeps a growth of TR_DYN_SHOOT_RETRY_PER;
 * else 0: the failure stands. */
int tr_dyn_retry_segments(const tr_model *m, double rhoA, double dt, double alpha, int st);
/* The run.  TR_OK; TR_EINVAL (spec out of range or a model the dynamics does not cover:
 * message says which); a failed step's status (out->done the last good one, message with
 * its time and why); TR_EBUDGET / TR_EINTERRUPTED. */
int tr_dyn_run(const tr_model *m, tr_data *d, const double *x0, const tr_dyn_spec *sp,
               tr_dyn_out *out);

#endif /* TR_DYN_H */
