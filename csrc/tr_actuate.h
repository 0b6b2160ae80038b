/*
 * tr_actuate.h -- inverse actuation (tendonrod.actuate): the controls of chosen tendons
 * (displacements q [m] or tensions tau [N], each tendon's own control kind) that bring
 * the tip to a target under the scene's loads.
 *
 * A run starts from a converged solve of the scene in its workspace.  A square target
 * whose controls are all displacements may first be solved inside the shooting system
 * (tr_data_set_target: one Newton solve).  Then come trust-region steps on the
 * linearisation of the current equilibrium, every accepted iterate a converged warm
 * solve: Levenberg-Marquardt where the target has at least as many components as there
 * are controls, a composite-step sequential quadratic program for the least change of the
 * controls where it has fewer (with the tensions of the tendons taut in the scene held
 * at a floor).  The state reached is solved once more, judged for stability on request.
 *
 * Units: a target's residual is dimensionless (positions / L, angles in radians);
 * controls are measured in scaled units, q by the largest tendon offset and tau by
 * EI / (r L) (either turns the tip by about a radian).
 */
#ifndef TR_ACTUATE_H
#define TR_ACTUATE_H

#include "tendonrod.h"

#ifdef __cplusplus
extern "C" {
#endif

/* What is asked of the controls. */
enum tr_act_kind {
    TR_ACT_SQUARE = 0,       /* as many controls as target components: Newton */
    TR_ACT_MIN_CHANGE = 1,   /* more controls: the least change from the scene's values */
    TR_ACT_LEAST_SQUARES = 2 /* fewer: the least-squares target residual */
};

/* How a run ended. */
enum tr_act_outcome {
    TR_ACT_DONE = 0,        /* the target met (square, least squares) or a KKT point */
    TR_ACT_STUCK = 1,       /* no step reduces the residual (a least-squares point where
                               res->optimal says so) */
    TR_ACT_UNREACHABLE = 2, /* the target lies beyond what the tensions allow */
    TR_ACT_MAX_ITER = 3,    /* out of iterations */
    TR_ACT_MOVED = 4,       /* (a step's outcome) moved to a new iterate */
    TR_ACT_REJECTED = 5     /* (a step's outcome) refused; the trust region shrank */
};

/* The tip target in the base frame (where the core reports the tip).  goal: the kinds of
 * tr_target_kind (TR_TARGET_ANGLE, TR_TARGET_DIRECTION, TR_TARGET_POSITION; a position
 * with has_R is a pose). */
typedef struct {
    int goal;
    int m;        /* components of the residual (1..6) */
    double theta; /* angle [rad]: the planar tip angle, unwrapped */
    double t[3];  /* direction: the unit target */
    double BT[6]; /* direction: (m x 3) rows, an orthonormal basis of the plane normal to t */
    double p[3];  /* position [m] */
    double R[9];  /* pose: body-to-base rotation, row-major */
    int has_R;    /* 1: a pose */
    int rows[6];  /* position / pose: the components of [dx / L (3), phi (3)] kept (m) */
    double L;     /* rod length [m] */
} tr_act_target;

/* One actuation.  Arrays belong to the caller and must outlive tr_actuate. */
typedef struct {
    int kind;             /* tr_act_kind */
    int n;                /* controls */
    const int *idx;       /* (n) the tendon of each control */
    const double *c0;     /* (n) the scene's control values: q [m] or tau [N] */
    const double *scale;  /* (n) their scales (q by r [m], tau by EI / (r L) [N]) */
    const double *values; /* (nt) the scene's actuation values of every tendon */
    const double *floor0; /* (nt) tension floors [N] (-inf: none) of the minimum change */
    double tau_scale;     /* EI / (r L) [N] */
    double k;             /* tau_scale / r [N/m]: signed tension psi = tau - k slack */
    double tol;           /* target tolerance on the residual's max-norm */
    int max_iter;         /* outer iterations */
    int tip_row;          /* the tip's breakpoint index (tr_linearize's rows) */
    int augmented;        /* 1: try the target inside the shooting system first (square,
                             displacement controls, a planar angle or a spatial direction
                             or position) */
    int judge;            /* 1: the final solve is judged for stability */
    tr_act_target target;
} tr_act_spec;

/* What a run did. */
typedef struct {
    int outcome;    /* tr_act_outcome of the last step */
    int optimal;    /* minimum change: a KKT point verified; square: the target reached;
                       least squares: reached, or a least-squares point */
    int augmented;  /* 1: the target was solved inside the shooting system first */
    int iterations; /* outer iterations */
    int solves;     /* equilibrium solves, the final one included */
    int jacobians;  /* linearisations */
    int status;     /* the final solve's status (TR_SUCCEEDED: its state is the answer) */
    /* The verdict (verdict() in tr_actuate.c): the final solve succeeded, and the target
     * was reached (square), reached at a verified KKT point (minimum change), or reached
     * or a least-squares point no state the run solved improves on (least squares).  The
     * state returned (square, least squares) is never worse than one the run solved. */
    int success;
    /* Square, least squares: max_j |a_j^T r| / (|a_j| |r|) at the state returned (least
     * squares: <= TR_ACT_GTOL a least-squares point; NaN: not measured there). */
    double optimality;
    int have_lam;   /* 1: lam and mus were set (minimum change) */
    double r[6];    /* (m) the target residual at the state returned */
    double lam[6];  /* (m) the target's multipliers (scaled units) */
    double *c;      /* (n) the controls found, caller's buffer */
    double *mus;    /* (nt) tension floors' multipliers, caller's buffer */
    double *floors; /* (nt) the final tension floors (-inf: none), caller's buffer */
    char why[128];  /* why the target was not reached, when the run knows ("" else) */
} tr_act_result;

/* Run the actuation from the workspace's current state, which must be a converged solve
 * of the scene at c0 (its last call succeeded); d->opt.accept_unstable should be set (the
 * iterates are not judged).  The workspace ends at the final solve's state; the model at
 * its controls, d->status that solve's status.  Returns TR_OK (the result filled; the
 * target may still be out of reach: res->outcome, res->r), TR_EINVAL for a spec this model
 * does not fit (message in d->message), TR_ENOMEM, or the status of a linearisation that
 * failed (TR_EBUDGET, TR_EINTERRUPTED, ...). */
int tr_actuate(const tr_model *m, tr_data *d, const tr_act_spec *spec, tr_act_result *res);

#ifdef __cplusplus
}
#endif
#endif /* TR_ACTUATE_H */
