/*
 * tr_continuation.c -- load continuation: from the unloaded straight robot, ramp
 * the actuation (loads off), then the loads, with an adaptive step (x2 on success,
 * x1/2 on failure), a secant predictor and full Newton per stage.
 */
#include <math.h>
#include <string.h>

#include "tendonrod.h"
#include "tr_internal.h"
#include "tru_math.h"

/* Tip position (world) of the state integrated from x (one evaluation). */
static void tip_of(const tr_model *m, tr_data *d, const double *x, double p[3])
{
    double R[9], n[3], mo[3];
    if (tr_residual(m, d, x, d->ft) != TR_OK) {
        p[0] = p[1] = p[2] = NAN;
        return;
    }
    tr_state_world(m, d->y, p, R, n, mo);
}

int tr_ramp(const tr_model *m_, tr_data *d, double *lamp, const char *what, double dmax)
{
    const tr_model *m = TR_IN(m_, d);
    const int k = d->k;
    const int iter_cap = d->opt.max_iter < TR_CONT_ITER ? d->opt.max_iter : TR_CONT_ITER;
    double lam = *lamp, dlam = TR_CONT_DLAM0 < dmax ? TR_CONT_DLAM0 : dmax, dlam_prev = 0.0;
    double tip[3], tip_new[3];
    int have_prev = 0, status, i;
    /* the tip of the solved start, to catch a load stage that jumps to another branch */
    if (lamp != &d->lam_act)
        tip_of(m, d, d->x, tip);
    else
        tip[0] = tip[1] = tip[2] = 0.0;
    while (lam < 1.0) {
        double lt;
        if (d->stop) {
            *lamp = lam;
            return d->stop;
        }
        if (dlam > dmax) dlam = dmax;
        lt = lam + dlam > 1.0 ? 1.0 : lam + dlam;
        if (d->nfev >= d->opt.max_nfev) {
            tr_set_message(d,
                           "function-evaluation limit (max_nfev = %d) reached during continuation "
                           "at %.4g of the %s; raise max_nfev",
                           d->opt.max_nfev, lam, what);
            *lamp = lam;
            return TR_EMAXFEV;
        }
        if (d->cont_steps >= d->opt.max_continuation) {
            tr_set_message(d,
                           "continuation reached only %.4g of the %s in max_continuation = %d "
                           "steps; raise max_continuation, or the scene may have no equilibrium on "
                           "this path (e.g. buckling, or a tendon that cannot hold the load)",
                           lam, what, d->opt.max_continuation);
            *lamp = lam;
            tr_watch_curvature(m, d, d->x, 1);
            return TR_ECONTINUATION;
        }
        memcpy(d->xs, d->x, (size_t)k * sizeof(double));
        memcpy(d->fs, d->f, (size_t)k * sizeof(double));
        if (have_prev)
            for (i = 0; i < k; i++) d->x[i] += (d->x[i] - d->xp[i]) * (lt - lam) / dlam_prev;
        *lamp = lt;
        status = tr_residual(m, d, d->x, d->f);
        d->fnorm = tru_maxnorm(d->f, k);
        if (status == TR_OK)
            status = tr_newton_run(m, d, iter_cap, TR_CONT_STALL_ITERS, TR_CONT_STALL_RATIO);
        d->cont_steps++;
        if (status == TR_EMAXFEV || d->stop) return status;
        if (status == TR_OK) {
            /* a stage whose tip jumps by more than TR_CONT_TIP_JUMP L left the branch it
             * started on (exponentially sensitive shapes can do that in one Newton
             * iteration): reject it and take a smaller step */
            if (lamp != &d->lam_act)
                tip_of(m, d, d->x, tip_new);
            else
                tip_new[0] = tip_new[1] = tip_new[2] = 0.0;
            if (lamp != &d->lam_act &&
                hypot(hypot(tip_new[0] - tip[0], tip_new[1] - tip[1]), tip_new[2] - tip[2]) >
                    TR_CONT_TIP_JUMP * m->L &&
                dlam > TR_CONT_DLAM_MIN * 4.0)
                status = TR_ENOPROGRESS;
        }
        if (status == TR_OK && d->ramp_stable) {
            /* a stage that ends unstable crossed a bifurcation or a limit point on the
             * way: smaller steps stay on the stable branch, or stall where it ends */
            tr_stability_quick(m, d);
            if (d->stable == 0) status = TR_ENOPROGRESS;
        }
        if (status == TR_OK) {
            memcpy(tip, tip_new, sizeof tip);
            memcpy(d->xp, d->xs, (size_t)k * sizeof(double));
            dlam_prev = lt - lam;
            lam = lt;
            have_prev = 1;
            dlam = 2.0 * dlam;
        } else {
            memcpy(d->x, d->xs, (size_t)k * sizeof(double));
            memcpy(d->f, d->fs, (size_t)k * sizeof(double));
            d->fnorm = tru_maxnorm(d->f, k);
            *lamp = lam;
            d->have_J = 0;
            have_prev = 0; /* the secant may point across a switch: predict constant */
            dlam *= 0.5;
            if (dlam < TR_CONT_DLAM_MIN) {
                tr_watch_curvature(m, d, d->x, 1);
                tr_set_message(d,
                               "continuation stalled at %.4g of the %s (step below %g): the "
                               "scene may have no equilibrium on this path (a limit point, "
                               "buckling, a tendon that cannot hold the load, or an impossible "
                               "actuation)",
                               lam, what, TR_CONT_DLAM_MIN);
                return TR_ECONTINUATION;
            }
        }
    }
    return TR_OK;
}

/* Continuation from the unloaded straight robot: first the actuation (loads
 * off), then the loads -- the order a robot is used in, which keeps an axial
 * load on a still-straight robot from buckling it on the way -- and with channel
 * friction, both frictionless, then the friction: a tendon sliding out with the
 * frictionless tension at the actuator can have its tension grow without bound along
 * s (tau' = mu tau |t'|), and one sliding in needs up to e^(mu theta) of it. */
static int continuation_run(const tr_model *m, tr_data *d)
{
    int status;
    d->lam_act = 0.0;
    d->lam_load = 0.0;
    if (m->nfric) d->lam_fric = 0.0;
    tr_cold_start(m, d);
    d->have_J = 0;
    status = tr_residual(m, d, d->x, d->f);
    d->fnorm = tru_maxnorm(d->f, d->k);
    if (status == TR_OK)
        status = tr_newton_run(m, d, d->opt.max_iter, TR_STALL_ITERS, TR_STALL_RATIO);
    if (status == TR_EMAXFEV || d->stop) return status;
    if (status != TR_OK) {
        tr_set_message(d, "continuation could not solve the unloaded robot: %s",
                       tr_strerror(status));
        return TR_ECONTINUATION;
    }
    status =
        tr_ramp(m, d, &d->lam_act, "actuation (tendon displacements and tensions, loads off)", 1.0);
    if (status != TR_OK) return status;
    /* load steps of at most TR_RAMP_LOAD (scaled F L^2/EI + M L/EI) keep the path on the
     * branch that grows from the unloaded robot; a model that chose multiple shooting for
     * its tensile loads leaves their scaled size (~ growth^2) out: tension stiffens the
     * rod and cannot loop it */
    {
        const double g = m->shoot_auto ? m->shoot_growth : 0.0;
        const double ls = tr_load_scale(m) - g * g;
        status = tr_ramp(m, d, &d->lam_load, "loads (at full actuation)",
                         ls > TR_RAMP_LOAD ? TR_RAMP_LOAD / ls : 1.0);
    }
    if (status != TR_OK || !m->nfric) return status;
    return tr_ramp(m, d, &d->lam_fric, "friction (at full actuation and loads)", 1.0);
}

int tr_continuation(const tr_model *m_, tr_data *d)
{
    const tr_model *m = TR_IN(m_, d);
    const int saved = d->jac_method;
    int status;
    d->jac_method = TR_JAC_NEWTON;
    status = continuation_run(m, d);
    d->jac_method = saved;
    d->lam_fric = 1.0; /* as the other parameters, restored by the caller after a stall */
    return status;
}
