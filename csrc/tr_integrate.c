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
int tr_segment_steps(const tr_model *m_, const tr_data *d, int seg)
{
    const tr_model *m = TR_IN(m_, d);
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

/* One classical RK4 step of length h from (s, y). */
static int rk4_step(tr_data *d, double s, double h, double *y, int dim)
{
    double *k1 = d->k1, *k2 = d->k2, *k3 = d->k3, *k4 = d->k4, *yt = d->yt;
    int j;
    if (tr_rhs(s, y, k1, d) != GSL_SUCCESS) return TR_ENONFINITE;
    for (j = 0; j < dim; j++) yt[j] = y[j] + 0.5 * h * k1[j];
    if (tr_rhs(s + 0.5 * h, yt, k2, d) != GSL_SUCCESS) return TR_ENONFINITE;
    for (j = 0; j < dim; j++) yt[j] = y[j] + 0.5 * h * k2[j];
    if (tr_rhs(s + 0.5 * h, yt, k3, d) != GSL_SUCCESS) return TR_ENONFINITE;
    for (j = 0; j < dim; j++) yt[j] = y[j] + h * k3[j];
    if (tr_rhs(s + h, yt, k4, d) != GSL_SUCCESS) return TR_ENONFINITE;
    for (j = 0; j < dim; j++) y[j] += h / 6.0 * (k1[j] + 2.0 * (k2[j] + k3[j]) + k4[j]);
    return TR_OK;
}

/* One fixed step (RK4 or rk8pd) of length h from (s, y). */
static int one_step(tr_data *d, int method, double s, double h, double *y, int dim)
{
    if (method == TR_RK4) return rk4_step(d, s, h, y, dim);
    if (gsl_odeiv2_step_apply(d->rec ? d->rk8_rec : d->rk8_shoot, s, h, y, d->yerr, NULL, NULL,
                              d->rec ? &d->sys_rec : &d->sys_shoot) != GSL_SUCCESS)
        return TR_ENONFINITE;
    return TR_OK;
}

/* The channels' normal loads tau t^' (3 per frictional tendon, 0 where slack) at (s, y). */
static int normals(tr_data *d, double s, const double *y, double *G)
{
    if (tr_rhs(s, y, d->ysw + d->vm->n_states_rec, d) != GSL_SUCCESS) return TR_ENONFINITE;
    memcpy(G, d->fric_g, 3 * (size_t)d->vm->nfric * sizeof(double));
    return TR_OK;
}

/* The first frictional tendon whose normal load G1 reverses against G0 (the friction
 * law's |tau t^'| has a kink where it passes through zero), skipping those in `done`;
 * -1 if none. */
static int reversal(int nf, const double *G0, const double *G1, const int *done)
{
    int k;
    for (k = 0; k < nf; k++) {
        const double *a = G0 + 3 * k, *b = G1 + 3 * k;
        if (!done[k] && a[0] * b[0] + a[1] * b[1] + a[2] * b[2] < 0.0) return k;
    }
    return -1;
}

/* A fixed step [s, s + h] of a model with friction.  Where a tendon's normal load reverses
 * inside the step, the right-hand side has a kink there and a step across it loses the
 * method's order; the step is split at the reversal, located by the Illinois variant of
 * regula falsi on G_k(sigma) . G_k(s) to TR_KINK_TOL of the step (each trial one step from
 * s), so that no step straddles it. */
static int kink_step(tr_data *d, int method, double s, double h, double *y, int dim, int *have)
{
    const tr_model *m = d->vm;
    const int nf = m->nfric;
    double *y0 = d->ysw, *G0 = d->fric_g + 3 * nf, *G1 = G0 + 3 * nf;
    int *done = d->fric_done, k, pass, st;
    const double s1 = s + h;
    for (k = 0; k < nf; k++) done[k] = 0;
    for (pass = 0; pass <= nf; pass++) {
        double a = s, b = s1, fa, fb, c = s1;
        int side = 0, it;
        memcpy(y0, y, (size_t)dim * sizeof(double));
        if (!*have && (st = normals(d, s, y, G0)) != TR_OK) return st;
        *have = 0;
        if ((st = one_step(d, method, s, s1 - s, y, dim)) != TR_OK) return st;
        if ((st = normals(d, s1, y, G1)) != TR_OK) return st;
        k = reversal(nf, G0, G1, done);
        if (k < 0) {
            /* the next step starts where this one ended */
            memcpy(G0, G1, 3 * (size_t)nf * sizeof(double));
            *have = 1;
            return TR_OK;
        }
        /* phi(sigma) = G_k(sigma) . G_k(s): positive at a, negative at b */
        fa = G0[3 * k] * G0[3 * k] + G0[3 * k + 1] * G0[3 * k + 1] + G0[3 * k + 2] * G0[3 * k + 2];
        fb = G1[3 * k] * G0[3 * k] + G1[3 * k + 1] * G0[3 * k + 1] + G1[3 * k + 2] * G0[3 * k + 2];
        for (it = 0; it < TR_KINK_ITER && b - a > TR_KINK_TOL * h; it++) {
            double fc, *Gc = G1;
            c = (a * fb - b * fa) / (fb - fa);
            if (!(c > a && c < b)) c = 0.5 * (a + b);
            memcpy(y, y0, (size_t)dim * sizeof(double));
            if ((st = one_step(d, method, s, c - s, y, dim)) != TR_OK) return st;
            if ((st = normals(d, c, y, Gc)) != TR_OK) return st;
            fc = Gc[3 * k] * G0[3 * k] + Gc[3 * k + 1] * G0[3 * k + 1] +
                 Gc[3 * k + 2] * G0[3 * k + 2];
            if (fc > 0.0) {
                a = c, fa = fc;
                if (side == 1) fb *= 0.5;
                side = 1;
            } else {
                b = c, fb = fc;
                if (side == -1) fa *= 0.5;
                side = -1;
            }
        }
        /* step to the reversal, then go on from there with the rest of the step */
        c = 0.5 * (a + b);
        memcpy(y, y0, (size_t)dim * sizeof(double));
        if ((st = one_step(d, method, s, c - s, y, dim)) != TR_OK) return st;
        done[k] = 1;
        s = c;
    }
    return one_step(d, method, s, s1 - s, y, dim);
}

int tr_integrate_with(const tr_model *m_, tr_data *d, int method, double s0, double s1, int nsteps,
                      double *y)
{
    const tr_model *m = TR_IN(m_, d);
    const int dim = d->rec ? m->n_states_rec : m->n_states;
    int status = TR_OK;
    if (!(s1 > s0)) return TR_OK;
    if (tr_poll(d)) return d->stop;
    switch (method) {
    case TR_RK4:
    case TR_RK8: {
        const double h = (s1 - s0) / nsteps;
        int step, have = 0;
        for (step = 0; step < nsteps && status == TR_OK; step++) {
            const double s = method == TR_RK4       ? s0 + step * h
                             : (step == nsteps - 1) ? s1 - h
                                                    : s0 + step * h;
            if ((step & TR_POLL_STEPS) == TR_POLL_STEPS && tr_poll(d)) {
                status = d->stop;
                break;
            }
            status = m->nfric ? kink_step(d, method, s, h, y, dim, &have)
                              : one_step(d, method, s, h, y, dim);
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

int tr_integrate(const tr_model *m_, tr_data *d, double s0, double s1, int nsteps, double *y)
{
    const tr_model *m = TR_IN(m_, d);
    return tr_integrate_with(m, d, d->opt.integrator, s0, s1, nsteps, y);
}
