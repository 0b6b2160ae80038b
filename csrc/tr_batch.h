/*
 * tr_batch.h -- many scenes of one robot design solved in one call (pure C99 + GSL).
 *
 * A batch shares everything that fixes the shape of the shooting problem with a
 * compiled base model: rod, tendon routing, control modes, load positions, the
 * formulation (planar/spatial); the model is only read, so threads may run batches of
 * one model at once.  Per point it varies only values (the inputs of its one workspace,
 * tr_data_set_values):
 *   - the actuation value of every tendon (q [m] for displacement-controlled tendons,
 *     tau [N] for tension-controlled ones, following the base model's control modes),
 *   - the force and moment of every point load (world frame),
 *   - the uniform distributed force (world frame).
 * Points are solved in order with the core's public API; each is warm-started from
 * the previous converged point (its base state, tr_base_state, and its final
 * Jacobian), as tendonrod.solve(scene, guess=previous) does, optionally (predict) from a
 * secant, quadratic or cubic prediction along a line of points, and off that line from
 * the nearer of the previous point and the first point of the last line.  With a fixed step
 * count (opt->steps > 0) a warm point first runs the lean solve (tr_solve_lean) and
 * goes to the full tr_solve only if that fails; with automatic steps every point runs
 * tr_solve (step verification included).  Only tip quantities are recorded.
 * One call uses one workspace: everything is allocated once at the start of
 * tr_batch_solve and freed at its end, nothing per point.  Call it from several
 * threads on disjoint ranges of points for parallelism (the base model is read-only
 * and may be shared).
 */
#ifndef TR_BATCH_H
#define TR_BATCH_H

#include <stddef.h>
#include "tendonrod.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct tr_batch_in {
    int n;                         /* number of points */
    const double *value;           /* (n x nt) actuation value per tendon: q [m] (> 0 retracts) or
                               tau [N] (>= 0), per the base model's control modes; NULL: the
                               base model's values at every point */
    const double *load;            /* (n x nl x 6) [F (3) N, M (3) N m], world frame, of every point
                               load of the base model (positions stay the base model's);
                               NULL: the base model's loads */
    const double *dist;            /* (n x 3) uniform distributed force, world frame [N/m]; NULL:
                               the base model's */
    int warm;                      /* 1: warm-start each point from the previous converged one */
    int retry_cold;                /* 1: a warm start that fails is retried cold (no guess) */
    int predict;                   /* 1: when a point continues the line through the last two
                               converged points, start from the extrapolation of their
                               solutions instead of the last one; else from the nearer
                               (scaled values) of the last one and the first point of
                               the last line */
    int exact;                     /* 1: reproduce a loop of tendonrod.solve(scene,
                                      guess=previous tip-only solution) bit for bit: no
                                      predictor, no lean solve (every point runs tr_solve) */
    int skip_tension_displacement; /* 1: a point solved by the lean solve skips the
                                      recording pass (tr_record_tip); the displacement of
                                      tension-controlled tendons is then NaN there (scenes
                                      whose tendons are all displacement-controlled never
                                      need that pass) */
    int (*poll)(void *ctx);        /* the caller's poll hook (tr_set_poll), or NULL */
    void *poll_ctx;
} tr_batch_in;

typedef struct tr_batch_out {
    double *tip_pos;      /* (n x 3) tip position, world [m] */
    double *tip_rot;      /* (n x 9) tip rotation body-to-world, row-major */
    double *tension;      /* (n x nt) tendon tension [N] */
    double *slack;        /* (n x nt) tendon slack [m] */
    double *displacement; /* (n x nt) actuator displacement [m] */
    double *residual;     /* (n) final scaled residual max-norm */
    int *status;          /* (n) tr_solve status of the point (0 ok, > 0 caveat, < 0 failure) */
    int *nit;             /* (n) iterations */
    int *nfev;            /* (n) residual evaluations (integrations) */
    int *cold;            /* (n) 1 if the point was solved without a guess; may be NULL */
    char *message;        /* (n x msglen) the solver's message for every point whose status
                               is not TR_OK (left untouched for TR_OK points); may be NULL */
    size_t msglen;
    double *unknowns; /* (n x m->n_unknowns) the point's final shooting unknowns (scaled, as the
                         core defines them; NaN where no solve ran), so that tr_record_from can
                         record its states later; may be NULL */
    int *steps;       /* (n) integrator steps of those unknowns (the tr_record_from argument; 0
                         for the adaptive integrator or where no solve ran); may be NULL */
    int *stable;      /* (n) the stability verdict of the point (tr_branch.c): 1 stable, 0
                         unstable, -1 not judged (no solution, Options.accept_unstable, or
                         undecided); may be NULL */
} tr_batch_out;

/* Solve in->n points of the base model m with options opt (tip_only is forced on).
 * Returns TR_OK when the workspace could be set up and every point was attempted
 * (per-point outcomes are in out->status), TR_EINTERRUPTED when the poll hook stopped
 * the batch (the points from there on have that status), TR_EINVAL (bad arguments;
 * msg says which) or TR_ENOMEM.  Per-point value problems (a negative prescribed tension, an
 * out-of-plane load on a planar model, a non-finite value) give that point
 * TR_EINVAL with a message and do not stop the batch. */
int tr_batch_solve(const tr_model *m, const tr_options *opt, const tr_batch_in *in,
                   tr_batch_out *out, char *msg, size_t msglen);

#ifdef __cplusplus
}
#endif
#endif /* TR_BATCH_H */
