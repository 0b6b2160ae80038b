/*
 * tr_solve.c -- the one-call driver, as a list of stages:
 *   1. begin:        reset the counters; a scene without a unique equilibrium stops here
 *   2. direct:       init from the guess (or the cold guess), Newton/Broyden; a cold
 *                    start under large loads goes to continuation at once
 *   3. continuation: on failure, follow the load path from the unloaded robot; if that
 *                    path stalls after a forced start, a direct cold solve may still
 *                    find an equilibrium off the path (TR_OFFPATH, not a success)
 *   4. verify:       automatic steps: step doubling until the truncation estimate <= tol
 *   5. condition:    a fresh Jacobian at a cold solution, polish, condition number
 *   6. diagnose:     what a failure is likely due to
 *   7. record:       the recording pass and the final message
 */
#include <math.h>
#include <string.h>

#include "tendonrod.h"
#include "tr_internal.h"

static int solve_begin(const tr_model *m, tr_data *d)
{
    int i;
    tr_solve_reset(m, d, d->opt.steps > 0 ? d->opt.steps : tr_auto_steps(m, d));
    if (d->model != m) {
        tr_set_message(d, "workspace was allocated for a different model");
        return TR_EINVAL;
    }
    if (m->scene_status == TR_OK) return TR_OK;
    /* nothing stale is handed back: the recorded states (pos, rot, force, moment, 18
     * per node, contiguous in one block) and the tendon outputs become NaN; the node
     * arc lengths d->s stay (inputs of the next recording pass) */
    tr_set_message(d, "%s", m->scene_message);
    for (i = 0; i < 18 * d->nnode; i++) d->pos[i] = NAN;
    for (i = 0; i < 3 * m->nt; i++) d->tension[i] = NAN;
    for (i = 0; i < d->k; i++) d->x[i] = NAN;
    d->have_J = 0;
    for (i = 0; i < d->k * d->k; i++) d->J[i] = NAN;
    return m->scene_status;
}

static int solve_direct(const tr_model *m, tr_data *d, const double *guess, const double *jac,
                        int *forced)
{
    int status = tr_solve_init(m, d, guess, jac);
    *forced = 0;
    if (status != TR_OK) return status;
    if (!guess && d->opt.continuation && d->opt.max_continuation > 0 &&
        tr_load_scale(m) > TR_DIRECT_LOAD_MAX) {
        /* large loads from a cold start: a direct Newton iteration can land on a looped,
         * unstable equilibrium (buckled-through elastica); follow the load path from
         * the unloaded robot instead */
        *forced = 1;
        tr_set_message(d, "large loads (scaled %.3g > %g): solved by continuation",
                       tr_load_scale(m), TR_DIRECT_LOAD_MAX);
        return TR_ECONTINUATION;
    }
    return tr_newton_run(m, d, d->opt.max_iter, TR_STALL_ITERS, TR_STALL_RATIO);
}

static int solve_continuation(const tr_model *m, tr_data *d, int status, int forced)
{
    char first[TR_MSGLEN], second[TR_MSGLEN], both[TR_MSGLEN];
    int st2, st3;
    if (!(status < 0 && status != TR_EMAXFEV && d->opt.continuation && d->opt.max_continuation > 0))
        return status;
    memcpy(first, d->message, TR_MSGLEN);
    st2 = tr_continuation(m, d);
    if (st2 == TR_OK) return TR_OK;
    memcpy(second, d->message, TR_MSGLEN);
    tr_set_message(d, "%s; then %s", first, second);
    if (st2 == TR_EMAXFEV) return st2;
    if (!forced) return TR_ECONTINUATION;
    /* the load path stalled (a limit point: snap-through): an equilibrium may still
     * exist off that path; a direct cold solve may find it */
    memcpy(both, d->message, TR_MSGLEN);
    d->lam_act = d->lam_load = 1.0;
    st3 = tr_solve_init(m, d, NULL, NULL);
    if (st3 == TR_OK) st3 = tr_newton_run(m, d, d->opt.max_iter, TR_STALL_ITERS, TR_STALL_RATIO);
    if (st3 != TR_OK) {
        tr_set_message(d, "%s; a direct solve did not converge either", both);
        return TR_ECONTINUATION;
    }
    tr_set_message(d,
                   "converged by a direct solve, but load continuation from the "
                   "unloaded robot stalled (%s): this equilibrium may not be the "
                   "one reached by loading the robot (a limit point / "
                   "snap-through lies on the path)",
                   second);
    return TR_OFFPATH;
}

static int solve_condition(const tr_model *m, tr_data *d, int status, const double *jac)
{
    /* A cold solve returns a fresh finite-difference Jacobian at the solution (the
     * Broyden-updated one is accurate only along recent steps): it makes the
     * condition estimate meaningful and warm starts from it Newton-fast.  Warm
     * solves keep the updated one (it came from a nearby fresh one). */
    if (status >= 0 && !jac && !d->J_fresh && d->k > 0 && tr_fd_jacobian(m, d) != TR_OK)
        d->have_J = 0;
    if (status >= 0 && d->have_J) tr_polish(m, d);
    d->jacobian_cond = d->have_J ? tr_jacobian_cond(d) : NAN;
    if (status >= 0 && d->jacobian_cond > TR_COND_SINGULAR) {
        tr_set_message(d,
                       "converged, but the Jacobian is nearly singular (condition %.3g): the "
                       "tendon tensions are poorly determined; if opposing inextensible tendons "
                       "act on an inextensible backbone the problem is statically indeterminate: "
                       "give the tendons a finite EA or the backbone an extension stiffness",
                       d->jacobian_cond);
        return TR_ILLCONDITIONED;
    }
    if (status < 0 && d->jacobian_cond > TR_COND_SINGULAR && m->ndisp >= 2) {
        char first[TR_MSGLEN];
        memcpy(first, d->message, TR_MSGLEN);
        tr_set_message(d,
                       "%s; the Jacobian is nearly singular (condition %.3g): the tendon "
                       "tensions may be statically indeterminate (give the tendons a finite EA "
                       "or the backbone an extension stiffness)",
                       first, d->jacobian_cond);
    }
    return status;
}

/* Stiff tendons sharing a tension level: that level is fixed only by their stretch,
 * a near-null direction of the Jacobian (singular value ~ EI/(r^2 EA)) along which
 * second-order shape terms spoil the Newton step. */
static void solve_diagnose(const tr_model *m, tr_data *d, int status)
{
    double stiff = 0.0;
    char first[TR_MSGLEN];
    int i;
    if (!(status < 0 && status != TR_EMAXFEV && m->ndisp >= 2)) return;
    for (i = 0; i < m->nt; i++) {
        const tr_tendon *t = m->tendon + i;
        const double ratio = t->b * t->b * t->EA / m->EI;
        if (t->control == TR_DISPLACEMENT && isfinite(t->EA) && ratio > stiff) stiff = ratio;
    }
    if (!(stiff > TR_STIFF_HINT)) return;
    memcpy(first, d->message, TR_MSGLEN);
    tr_set_message(d,
                   "nearly inextensible tendons (r^2 EA/EI up to %.3g: the tension "
                   "level they share is set only by their stretch, poorly resolved by "
                   "Newton; try a softer EA, or a guess solved with softer tendons): %s",
                   stiff, first);
}

static int solve_record(const tr_model *m, tr_data *d, int status)
{
    int rs;
    d->residual_norm = d->fnorm;
    d->lam_act = d->lam_load = 1.0;
    rs = tr_record(m, d);
    if (rs != TR_OK && status >= 0) {
        status = rs;
        tr_set_message(d, "the recording pass failed: %s", tr_strerror(rs));
    }
    if (status == TR_OK)
        tr_message_converged(d->message, TR_MSGLEN, d->nit, d->residual_norm, d->opt.tol);
    else if (status == TR_TRUNCATION && d->message[0] == '\0')
        tr_set_message(d, "%s", tr_strerror(status));
    return status;
}

int tr_solve(const tr_model *m, tr_data *d, const double *guess, const double *jac)
{
    int status, forced;
    status = solve_begin(m, d);
    if (status != TR_OK) return d->status = status;
    status = solve_direct(m, d, guess, jac, &forced);
    if (status == TR_EINVAL) return d->status = status;
    status = solve_continuation(m, d, status, forced);
    if (status >= 0 && d->opt.steps == 0 && d->opt.integrator != TR_ADAPTIVE) {
        const int vs = tr_verify_steps(m, d);
        if (vs != TR_OK) status = vs;
    }
    status = solve_condition(m, d, status, jac);
    solve_diagnose(m, d, status);
    return d->status = solve_record(m, d, status);
}
