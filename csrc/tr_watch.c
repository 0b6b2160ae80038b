/*
 * tr_watch.c -- does a tendon approach the centre of curvature?
 *
 * A taut tendon at offset r from the centre line has the path-length rate
 * |w| = |v + u x r + r'|; where the backbone bends toward it with curvature 1/r
 * (tension near EI / r^2 at a moment-free end) |w| vanishes and the tendon would pass
 * the centre of curvature: the model has no equilibrium past that point.  When a load
 * path stalls, the state it stalled on is walked along s and the smallest rate
 * |w| / |w_ref| of a taut tendon is kept with its tendon, arc length, tension and the
 * limit EI / r^2, so that the failure can name them even when the stall happens below
 * the limit.
 */
#include <math.h>
#include <stdio.h>

#include "tendonrod.h"
#include "tr_internal.h"
#include "tru_math.h"

/* Sub-steps of the walk per rod length, at least (the closest approach to 1/r is located
 * to L / TR_WATCH_STEPS or to a shooting step, whichever is finer). */
#define TR_WATCH_STEPS 32

/* |w| of tendon i at s on state y (shooting layout); its offset |r| into *rr */
static double rate_of(const tr_model *m, int i, double s, const double *y, double *rr)
{
    const double h = 1e-6 * m->L;
    double th[3], r[3], ra[3], rb[3], rp[3], u[3] = {0, 0, 0}, v[3] = {0, 0, 1}, w[3];
    int c;
    tr_tendon_tangent(m, i, s, y, th, r);
    tr_tendon_tangent(m, i, s - h, y, th, ra);
    tr_tendon_tangent(m, i, s + h, y, th, rb);
    for (c = 0; c < 3; c++) rp[c] = (rb[c] - ra[c]) / (2.0 * h);
    if (m->planar) {
        u[1] = y[TR_YP_M] / m->EI;
        if (!m->kirchhoff) {
            v[0] = y[TR_YP_N1] / m->GA;
            v[2] = 1.0 + y[TR_YP_N3] / m->EA;
        }
    } else {
        const double *nb = y + TR_Y_N, *mb = y + TR_Y_M;
        u[0] = mb[0] / m->EI;
        u[1] = mb[1] / m->EI;
        u[2] = mb[2] / m->GJ;
        if (!m->kirchhoff) {
            v[0] = nb[0] / m->GA;
            v[1] = nb[1] / m->GA;
            v[2] = 1.0 + nb[2] / m->EA;
        }
    }
    tru_cross3(w, u, r);
    for (c = 0; c < 3; c++) w[c] += v[c] + rp[c];
    *rr = tru_norm3(r);
    return tru_norm3(w);
}

/* the smallest rate of the taut tendons active on segment k at s; updates *best */
static void check_at(const tr_model *m, const tr_data *d, int k, double s, const double *y,
                     double *best, int *bi, double *bs, double *br)
{
    int c;
    for (c = m->seg_act_start[k]; c < m->seg_act_start[k + 1]; c++) {
        const int i = m->seg_act[c];
        double rr, rate;
        if (!(d->tau[i] > 0.0)) continue;
        rate = rate_of(m, i, s, y, &rr) / m->tendon[i].wref;
        if (rate < *best && rr > 0.0) {
            *best = rate;
            *bi = i;
            *bs = s;
            *br = rr;
        }
    }
}

double tr_watch_curvature(const tr_model *m, tr_data *d, const double *x, int keep)
{
    double *y = d->y, best = INFINITY, bs = NAN, br = NAN;
    int k, j, c, bi = -1;
    if (m->nt == 0 || d->k == 0) return NAN;
    d->rec = 0;
    d->nfev++;
    d->y_steps = -1;
    tr_set_tensions(m, d, x);
    tr_init_state(m, d, x, y, m->n_states);
    for (k = 0; k < m->nseg; k++) {
        const double s0 = m->bp[k], s1 = m->bp[k + 1];
        int n = tr_segment_steps(m, d, k);
        const int nmin = (int)ceil(TR_WATCH_STEPS * (s1 - s0) / m->L);
        if (n < nmin) n = nmin;
        d->seg = k;
        check_at(m, d, k, s0, y, &best, &bi, &bs, &br);
        for (j = 0; j < n; j++) {
            const double sa = s0 + (s1 - s0) * j / n, sb = s0 + (s1 - s0) * (j + 1) / n;
            if (tr_integrate(m, d, sa, sb, 1, y) != TR_OK) return NAN;
            check_at(m, d, k, sb, y, &best, &bi, &bs, &br);
        }
        if (k + 1 < m->nseg) {
            tr_apply_jump(m, d, k + 1, y);
            if (m->bp_node[k + 1] > 0) {
                const int o = tr_node_off(m, m->bp_node[k + 1]);
                for (c = 0; c < m->n_states; c++) y[c] = x[o + c] * tr_node_scale(m, c);
            }
        }
    }
    if (bi < 0) return NAN;
    if (keep == 2 || (keep == 1 && (!d->watch_have || best < d->watch_rate))) {
        d->watch_have = 1;
        d->watch_rate = best;
        d->watch_tendon = bi;
        d->watch_s = bs;
        d->watch_tau = d->tau[bi];
        d->watch_limit = m->EI / (br * br);
        d->watch_act = d->lam_act;
        d->watch_load = d->lam_load;
    }
    return best;
}

/* The named reason from d->watch_*, the state placed by `where`; 0 if the kept rate is
 * not below TR_WATCH_RATE. */
static int watch_format(const tr_data *d, const char *where, char *buf, size_t len)
{
    if (!d->watch_have || !(d->watch_rate < TR_WATCH_RATE)) return 0;
    snprintf(buf, len,
             "tendon %d would pass the centre of curvature: %s its "
             "path-length rate |w| fell to %.3g of the straight robot's "
             "at s = %.4g m, with tension %.4g N against the limit EI/r^2 = %.4g N there (the "
             "backbone curvature approaches 1/r); the model has no equilibrium past that "
             "point on this path (reduce the load or the actuation, or route the tendon "
             "closer to the centre line)",
             d->watch_tendon, where, d->watch_rate, d->watch_s, d->watch_tau, d->watch_limit);
    return 1;
}

int tr_watch_message(const tr_model *m, const tr_data *d, char *buf, size_t len)
{
    char where[128];
    (void)m;
    if (d->watch_act < 1.0)
        snprintf(where, sizeof where, "where the solve stalled (at %.4g of the actuation)",
                 d->watch_act);
    else if (d->watch_load < 1.0)
        snprintf(where, sizeof where, "where the solve stalled (at %.4g of the loads)",
                 d->watch_load);
    else
        snprintf(where, sizeof where, "where the solve stalled (at the full loads)");
    return watch_format(d, where, buf, len);
}

int tr_watch_named(const tr_model *m, tr_data *d, const double *x, const char *where, char *buf,
                   size_t len)
{
    d->watch_have = 0;
    d->lam_act = d->lam_load = 1.0;
    tr_watch_curvature(m, d, x, 2);
    return watch_format(d, where, buf, len);
}
