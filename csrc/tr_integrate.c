/*
 * tr_integrate.c -- integrate the rod ODE over one segment.
 *
 * Fixed steps: classical RK4 (written here) or GSL's rk8pd (Prince-Dormand
 * 8th order) driven with fixed steps through gsl_odeiv2_step_apply; or GSL's
 * adaptive evolve/control (rk8pd, scaled error control) for reference
 * solutions.  All workspaces come from tr_data; nothing allocates here.
 */
#include <math.h>
#include <string.h>
#include <gsl/gsl_errno.h>

#include "tendonrod.h"
#include "tr_internal.h"

/* Number of fixed steps on segment seg: the total spread in proportion to
 * length, at least one. */
int tr_segment_steps(const tr_model *m, const tr_data *d, int seg)
{
    const double len = m->bp[seg + 1] - m->bp[seg];
    const double nk = floor(d->steps * len / m->L + 0.5);
    return (nk < 1.0 ? 1 : (int)nk) * (d->steps_double ? 2 : 1);
}

static int all_finite(const double *y, int n)
{
    int i;
    for (i = 0; i < n; i++)
        if (!isfinite(y[i])) return 0;
    return 1;
}

static int rk4(const tr_model *m, tr_data *d, double s0, double s1, int n, double *y, int dim)
{
    const double h = (s1 - s0) / n;
    double *k1 = d->k1, *k2 = d->k2, *k3 = d->k3, *k4 = d->k4, *yt = d->yt;
    int step, j;
    for (step = 0; step < n; step++) {
        const double s = s0 + step * h;
        if ((step & TR_POLL_STEPS) == TR_POLL_STEPS && tr_poll(d)) return d->stop;
        if (tr_rhs(s, y, k1, d) != GSL_SUCCESS) return TR_ENONFINITE;
        for (j = 0; j < dim; j++) yt[j] = y[j] + 0.5 * h * k1[j];
        if (tr_rhs(s + 0.5 * h, yt, k2, d) != GSL_SUCCESS) return TR_ENONFINITE;
        for (j = 0; j < dim; j++) yt[j] = y[j] + 0.5 * h * k2[j];
        if (tr_rhs(s + 0.5 * h, yt, k3, d) != GSL_SUCCESS) return TR_ENONFINITE;
        for (j = 0; j < dim; j++) yt[j] = y[j] + h * k3[j];
        if (tr_rhs(s + h, yt, k4, d) != GSL_SUCCESS) return TR_ENONFINITE;
        for (j = 0; j < dim; j++) y[j] += h / 6.0 * (k1[j] + 2.0 * (k2[j] + k3[j]) + k4[j]);
    }
    return TR_OK;
}

int tr_integrate_with(const tr_model *m, tr_data *d, int method, double s0, double s1, int nsteps,
                      double *y)
{
    const int dim = d->rec ? m->n_states_rec : m->n_states;
    int status = TR_OK;
    if (!(s1 > s0)) return TR_OK;
    if (tr_poll(d)) return d->stop;
    switch (method) {
    case TR_RK4: status = rk4(m, d, s0, s1, nsteps, y, dim); break;
    case TR_RK8: {
        gsl_odeiv2_step *st = d->rec ? d->rk8_rec : d->rk8_shoot;
        const gsl_odeiv2_system *sys = d->rec ? &d->sys_rec : &d->sys_shoot;
        const double h = (s1 - s0) / nsteps;
        int step;
        for (step = 0; step < nsteps; step++) {
            const double s = (step == nsteps - 1) ? s1 - h : s0 + step * h;
            if ((step & TR_POLL_STEPS) == TR_POLL_STEPS && tr_poll(d)) {
                status = d->stop;
                break;
            }
            if (gsl_odeiv2_step_apply(st, s, h, y, d->yerr, NULL, NULL, sys) != GSL_SUCCESS) {
                status = TR_ENONFINITE;
                break;
            }
        }
        break;
    }
    case TR_ADAPTIVE: {
        gsl_odeiv2_step *st = d->rec ? d->ad_step_rec : d->ad_step_shoot;
        gsl_odeiv2_control *ctl = d->rec ? d->ad_ctl_rec : d->ad_ctl_shoot;
        gsl_odeiv2_evolve *ev = d->rec ? d->ad_ev_rec : d->ad_ev_shoot;
        const gsl_odeiv2_system *sys = d->rec ? &d->sys_rec : &d->sys_shoot;
        /* cap on adaptive steps per call: far beyond any smooth rod (1e5) */
        const long max_steps = 100000;
        double s = s0, h = (s1 - s0) / 8.0;
        long count = 0;
        gsl_odeiv2_evolve_reset(ev);
        gsl_odeiv2_step_reset(st);
        while (s < s1) {
            int gs;
            if (tr_poll(d)) {
                status = d->stop;
                break;
            }
            gs = gsl_odeiv2_evolve_apply(ev, ctl, st, sys, &s, s1, &h, y);
            if (gs != GSL_SUCCESS) {
                status = TR_EINTEGRATOR;
                break;
            }
            if (++count > max_steps) {
                status = TR_EINTEGRATOR;
                break;
            }
        }
        break;
    }
    default: status = TR_EINVAL;
    }
    if (status == TR_OK && !all_finite(y, dim)) status = TR_ENONFINITE;
    return status;
}

int tr_integrate(const tr_model *m, tr_data *d, double s0, double s1, int nsteps, double *y)
{
    return tr_integrate_with(m, d, d->opt.integrator, s0, s1, nsteps, y);
}
