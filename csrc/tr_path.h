/*
 * tr_path.h -- load paths: pseudo-arclength continuation of one equilibrium branch as
 * one scalar value of a compiled model varies, through limit points, with the limit and
 * bifurcation points on it located and (on request) a switch onto the branch that
 * crosses it at the first bifurcation.
 */
#ifndef TR_PATH_H
#define TR_PATH_H

#include "tendonrod.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The parameter kind for an entry of the value vector [actuation values (nt), point loads
 * (nl x 6: F (3) N, M (3) N m, world), distributed force (3) N/m, world]; the other kinds
 * are the design kinds of tr_param_kind (TR_PAR_ROD_EI .. TR_PAR_SLOPE). */
#define TR_PATH_SLOT (-1)

/* What a point of a path is. */
enum tr_path_point {
    TR_PT_REGULAR = 0,    /* a point of the branch */
    TR_PT_LIMIT = 1,      /* a limit point (fold): the parameter is extremal along the branch */
    TR_PT_BIFURCATION = 2 /* a simple bifurcation point: another branch crosses */
};

typedef struct {
    int kind;      /* TR_PATH_SLOT, or a design tr_param_kind */
    int index;     /* slot of the value vector, or the tendon of a tendon design kind */
    double p0, p1; /* the span: the parameter runs from p0 (the model's value) toward p1, in
                      the parameter's unit; lambda = (p - p0) / (p1 - p0) */
    double ds0;    /* first step along the path, in the scaled unknowns and lambda */
    double ds_max; /* largest step, same measure */
    int side;      /* 0: follow the branch through bifurcations; +1 / -1: at the first
                      bifurcation switch onto the crossing branch, along the null vector
                      whose largest component is positive / negative */
} tr_path_spec;

/* The points of a path, in order along it (special points where they lie): arrays of cap
 * rows given by the caller. */
typedef struct {
    int cap;            /* rows of each array */
    int n;              /* points stored */
    double *par;        /* (cap) parameter value [its unit] */
    double *tip;        /* (cap x 18) tip state: p (3) world [m], R (9) row-major, internal
                          force (3) [N], moment (3) [N m], world */
    double *tension;    /* (cap x nt) tendon tensions [N] */
    double *margin;     /* (cap) stability margin [EI/L] (NaN: not computed) */
    int *stable;        /* (cap) 1 stable, 0 unstable, -1 not decided (critical/neutral) */
    int *kind;          /* (cap) tr_path_point */
    int *branch;        /* (cap) 0 on the first branch, 1 after a switch */
    double *tlam;       /* (cap) the lambda component of the unit tangent (along the path) */
    double *x;          /* (cap x k) scaled unknowns */
    int *steps;         /* (cap) verified step count */
    double *residual;   /* (cap) scaled residual max-norm */
    double *truncation; /* (cap) truncation estimate (scaled residual; NaN: not estimated) */
} tr_path_out;

/* Follow the branch through the solution of m at p0 (solved first with tr_solve) toward p1,
 * storing each converged, verified, judged point in out; m's value of the parameter moves
 * along the path (and stays at the last point's).  Stops at p1 (a point exactly there),
 * where the branch returns to p0, when out is full or when a step cannot be taken (message
 * in d->message; the solver's reason kept).  TR_OK when p1 was reached; else the status of
 * the stop (TR_ECONTINUATION: full or stalled; TR_EINTERRUPTED; the start's failure).
 * Allocates its work arrays once, before its loop. */
int tr_path(const tr_model *m, tr_data *d, const tr_path_spec *spec, tr_path_out *out);

#ifdef __cplusplus
}
#endif
#endif /* TR_PATH_H */
