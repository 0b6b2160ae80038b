/*
 * tr_act_run.h -- the solves and linearisations of one inverse actuation (tr_actuate.h),
 * counted, and the states they converged to: shared by tr_act_run.c (the run) and
 * tr_actuate.c (its outer iteration).  Internal to the core.
 */
#ifndef TR_ACT_RUN_H
#define TR_ACT_RUN_H

#include <stddef.h>

#include "tendonrod.h"
#include "tr_data.h"
#include "tr_actuate.h"

/* How many of the last solves a return to their controls restarts from (of the ACT_POOL
 * converged states a run keeps, tr_data.h). */
#define ACT_CACHE 8

/* A step of Levenberg-Marquardt (square and least-squares targets) is accepted only where
 * the solved residual vector bears out the linearisation: |r_new - (r + A u)| <=
 * TR_ACT_FIDELITY |A u| (Deuflhard's affine-covariant test for Gauss-Newton: a step whose
 * second-order term exceeds half its first-order one left the linearisation's region,
 * however much it reduced |r|).  The region grows only where that ratio stays below half
 * of it.  Without the test a step into a poorly determined direction (a small singular
 * value of A, a large step) is accepted for the decrease it happens to give and carries
 * the iteration into another basin of |r|^2 (bench/results/trust_gaps.md, item 1). */
#define TR_ACT_FIDELITY 0.5
/* A least-squares point: for every control j, |a_j^T r| <= TR_ACT_GTOL |a_j| |r| (the
 * cosine between the residual and each column of the linearisation A, MINPACK's gtol
 * test; the components a bound active at the state blocks left out).  At a cosine of
 * 1e-4 a step along the linearisation could reduce |r| by cos^2 / 2 = 5e-9 of itself at
 * most, below what the solves resolve: the warm solves' tip noise (~1e-11 L) limits the
 * cosine the iteration can reach to about sqrt(2e-11 L / |r|), 2e-5 at |r| = 0.05 L (the
 * collapses measured ended at 1.6e-6 and 3.2e-6). */
#define TR_ACT_GTOL 1e-4

/* A converged state: what a solve from it needs and what the iteration reads. */
typedef struct {
    double *g;       /* (6 + 2 nt) the physical guess [n(0), m(0), tension, slack] */
    double *x;       /* (k) scaled unknowns */
    double *J;       /* (k x k) the solve's Jacobian */
    double *xver;    /* (k) its step verification's unknowns (have_ver) */
    double *valver;  /* (nt) and actuation values (have_valver) */
    double *tension; /* (nt) [N] */
    double *slack;   /* (nt) [m] */
    double *key;     /* (n) the control values it was solved at (tensions clipped at 0) */
    double tip[12];  /* tip position (3) [m] and rotation (9, row-major), base frame */
    double tip_angle, estver;
    double r[6];  /* (m) the target residual */
    double D[36]; /* (m x 6) its derivative by the tip's [dx, dtheta] */
    int have_ver, have_valver, steps;
    long born; /* the solve count when it was made (0: free) */
} act_state;

typedef struct {
    const tr_model *m;
    tr_data *d;
    const tr_act_spec *sp;
    int n, nt, k, mt; /* controls, tendons, unknowns, target components */
    act_state pool[ACT_POOL];
    int cache[ACT_CACHE], ncache; /* pool slots of the last solves, oldest first */
    int last;                     /* the last successful solve's slot */
    int best;    /* square and least squares: the slot of the least |r|^2 solved (-1: none) */
    int cur;     /* the iteration's current state's slot */
    int ws_ok;   /* 1: the workspace holds the last solve, a success */
    double *jac; /* (k x k) the last linearisation's shooting Jacobian (have_jac) */
    int have_jac;
    int polish; /* iterate solves take a Newton step past convergence */
    int solves, jacobians;
    long made;    /* states made so far (a state's born) */
    int stop;     /* nonzero: the status that ends the run (interrupted, out of budget) */
    double *vals; /* (nt) actuation values of the solve */
    double *key;  /* (n) */
    double *pose, *ten, *sl; /* linearisation: (nt x 6), (nt x nt), (nt x nt) */
    tr_param *par;           /* (nt) its parameters: every tendon's value */
    double *lsq;             /* tr_act_lstsq's workspace */
    double *block;           /* the one block of doubles the buffers above are in */
} act_run;

/* TR_OK, or TR_EINVAL (message in d->message) for a spec that does not fit the model or
 * a workspace without a converged solve to start from. */
int tr_act_check_spec(const tr_model *m, tr_data *d, const tr_act_spec *sp);
/* The run a (the caller's) set up, its buffers taken from the workspace (tr_data_take:
 * its TR_ALLOC_CALLS reserve, else allocated); 0, or -1 out of memory.  Give them back
 * with tr_act_run_free. */
int tr_act_run_alloc(act_run *a, const tr_model *m, tr_data *d, const tr_act_spec *sp);
void tr_act_run_free(act_run *a);
/* The workspace's current state (a converged solve at the scene's controls) as the
 * run's first: its slot. */
int tr_act_run_first(act_run *a);
/* A solve at controls c (n): warm from the last success with the last linearisation's
 * Jacobian where there is one, from the state solved at the same controls before with
 * its own, or from the guess `state` (6 + 2 nt; NULL: none) with that Jacobian.  Its
 * slot, or -1 when it failed (a->stop set when the run must end). */
int tr_act_solve(act_run *a, const double *c, const double *state);
/* The linearisation at slot s, with the sides `side` (nt: +1, -1, 0) wanted for tendons
 * at their switch: A (m x n) the target residual's and T (nt x n) the signed tensions'
 * derivatives by the scaled controls, sw (nt) the sides given.  TR_OK or the failure. */
int tr_act_linearize(act_run *a, int s, const double *side, double *A, double *T, int *sw);
/* |r|^2 of slot s: the least-squares objective (twice it). */
double tr_act_rr(const act_run *a, int s);
/* The signed tension psi = tau - k slack (nt) [N] of slot s. */
void tr_act_psi(const act_run *a, int s, double *psi);
/* The target solved inside the shooting system at the current state: the slot of the
 * forward solve of the controls found (c set), or -1 (nothing changed but counters). */
int tr_act_augmented(act_run *a, double *c);
/* The final solve at controls c from slot s, judged for stability on request: its
 * status, and its target residual in r (m; slot s's where it failed).  The workspace
 * ends there. */
int tr_act_final(act_run *a, int s, const double *c, int judge, double *r);
/* Least-norm least squares: x (cols) minimising |M x - b| (M rows x cols, row-major),
 * singular values below rcond times the largest dropped.  0, or -1 (SVD failed). */
int tr_act_lstsq(act_run *a, int rows, int cols, const double *M, const double *b, double rcond,
                 double *x);

#endif /* TR_ACT_RUN_H */
