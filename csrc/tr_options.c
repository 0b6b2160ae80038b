/*
 * tr_options.c -- the solver options: defaults (each with its reason in
 * tendonrod.h) and the one check of their ranges.
 */
#include <math.h>

#include "tendonrod.h"
#include "tr_internal.h"

tr_options tr_default_options(void)
{
    tr_options o;
    o.integrator = TR_RK8;
    o.steps = 0;
    o.rtol = 1e-10;
    o.tol = 1e-10;
    o.max_iter = 50;
    o.max_nfev = 20000;
    o.jacobian_method = TR_JAC_FD;
    o.slack_model = TR_SLACK_LINEAR;
    o.continuation = 1;
    o.max_continuation = 64;
    o.force_spatial = 0;
    o.tip_only = 0;
    o.shooting_segments = 1;
    o.auto_shooting = 1;
    o.max_work = TR_DEFAULT_MAX_WORK;
    o.max_time = 0.0;
    o.accept_unstable = 0;
    return o;
}

/* An int option in [lo, hi]. */
static int check_int(const char *name, int v, int lo, int hi, char *msg, size_t msglen)
{
    if (v >= lo && v <= hi) return TR_OK;
    tr_msgf(msg, msglen, "%s = %d must lie in [%d, %d]", name, v, lo, hi);
    return TR_EINVAL;
}

int tr_options_check(const tr_options *o, char *msg, size_t msglen)
{
    if (!o) {
        tr_msgf(msg, msglen, "options: NULL");
        return TR_EINVAL;
    }
    if (check_int("integrator", o->integrator, TR_RK4, TR_ADAPTIVE, msg, msglen) ||
        check_int("steps", o->steps, 0, TR_MAX_STEPS, msg, msglen) ||
        check_int("max_iter", o->max_iter, 1, TR_MAX_ITER_CAP, msg, msglen) ||
        check_int("max_nfev", o->max_nfev, 1, TR_MAX_NFEV_CAP, msg, msglen) ||
        check_int("jacobian_method", o->jacobian_method, TR_JAC_FD, TR_JAC_HYBRID, msg, msglen) ||
        check_int("slack_model", o->slack_model, TR_SLACK_LINEAR, TR_SLACK_SQUARED, msg, msglen) ||
        check_int("continuation", o->continuation, 0, 1, msg, msglen) ||
        check_int("max_continuation", o->max_continuation, 0, TR_MAX_CONTINUATION_CAP, msg,
                  msglen) ||
        check_int("force_spatial", o->force_spatial, 0, 1, msg, msglen) ||
        check_int("tip_only", o->tip_only, 0, 1, msg, msglen) ||
        check_int("auto_shooting", o->auto_shooting, 0, 1, msg, msglen) ||
        check_int("shooting_segments", o->shooting_segments, 1, TR_MAX_SHOOTING_SEGMENTS, msg,
                  msglen))
        return TR_EINVAL;
    /* below ~1e-14 no double-precision step can meet the tolerance: the adaptive
     * integrator would shrink its step to underflow (seconds per evaluation) */
    if (!(o->rtol >= TR_RTOL_MIN && o->rtol < 1.0)) {
        tr_msgf(msg, msglen, "rtol = %g must lie in [%g, 1) (double precision cannot deliver less)",
                o->rtol, TR_RTOL_MIN);
        return TR_EINVAL;
    }
    if (!(o->tol > 0.0 && o->tol < 1.0)) {
        tr_msgf(msg, msglen, "tol = %g must lie in (0, 1)", o->tol);
        return TR_EINVAL;
    }
    if (!(o->max_work >= 1.0 && o->max_work <= TR_MAX_WORK_CAP)) {
        tr_msgf(msg, msglen, "max_work = %g must lie in [1, %g]", o->max_work, TR_MAX_WORK_CAP);
        return TR_EINVAL;
    }
    if (!(o->max_time >= 0.0 && o->max_time <= TR_MAX_TIME_CAP)) {
        tr_msgf(msg, msglen, "max_time = %g s must lie in [0, %g] (0: no limit)", o->max_time,
                TR_MAX_TIME_CAP);
        return TR_EINVAL;
    }
    return TR_OK;
}

double tr_shooting_growth(const tr_model *m)
{
    const double h = m->L / TR_GROWTH_SAMPLES;
    double g = 0.0;
    int j, i;
    for (j = 0; j < TR_GROWTH_SAMPLES; j++) {
        const double s = (j + 0.5) * h;
        double N = m->dist[2] * (m->L - s);
        for (i = 0; i < m->nl; i++) {
            const double *ld = m->load + TR_LD_NCOL * i;
            if (ld[TR_LD_S] >= s) N += ld[TR_LD_F + 2];
        }
        for (i = 0; i < m->nd; i++) {
            const double *dl = m->dload + TR_DL_NCOL * i;
            const double a = dl[TR_DL_S0] > s ? dl[TR_DL_S0] : s;
            if (dl[TR_DL_S1] > a) N += dl[TR_DL_F + 2] * (dl[TR_DL_S1] - a);
        }
        if (N > 0.0) g += sqrt(N / m->EI) * h;
    }
    return g;
}

int tr_auto_segments(double growth)
{
    double M;
    if (!(growth > TR_AUTO_SHOOT_GROWTH)) return 1;
    M = ceil(growth / TR_AUTO_SHOOT_PER);
    if (M < 2.0) M = 2.0;
    return M > TR_MAX_SHOOTING_SEGMENTS ? TR_MAX_SHOOTING_SEGMENTS : (int)M;
}

double tr_work_budget(const tr_data *d)
{
    return d->opt.max_work;
}
