/* The element Hessian in the reduced variables (tr_elem_hessian: a Cosserat element's
 * positions through the chord p_b - p_a only, 45 hyper-dual passes) against one
 * hyper-dual pass per pair of all 12 coordinates (tr_elem_energy) on random elements:
 * Cosserat and Kirchhoff, three tendons (one helical) at random tensions (some slack),
 * random node frames a moderate relative turn apart, random free strains and dead forces,
 * node a free or clamped.  The reduction is exact, so they agree to round-off: the bound
 * 1e-12 of the Hessian's largest entry leaves room for the position entries, which come
 * from the same passes but with a different seed and sign.  Exit 0 on success; prints the
 * worst relative difference. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <gsl/gsl_errno.h>
#include "tendonrod.h"
#include "tr_element.h"
#include "tr_internal.h"

static double urand(unsigned *s)
{
    *s = *s * 1103515245u + 12345u;
    return ((*s >> 8) & 0xffffff) / 16777216.0 * 2.0 - 1.0;
}

/* a rotation: exp of a random rotation vector of size up to amp, times R0 */
static void rand_rot(unsigned *s, double amp, const double *R0, double *R)
{
    double w[3], th, K[9], E[9];
    int i, j, k;
    for (i = 0; i < 3; i++) w[i] = amp * urand(s);
    th = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    K[0] = K[4] = K[8] = 0, K[1] = -w[2], K[2] = w[1], K[3] = w[2], K[5] = -w[0], K[6] = -w[1];
    K[7] = w[0];
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++) {
            double kk = 0;
            for (k = 0; k < 3; k++) kk += K[3 * i + k] * K[3 * k + j];
            E[3 * i + j] = (i == j) + sin(th) / th * K[3 * i + j] + (1 - cos(th)) / (th * th) * kk;
        }
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++) {
            double acc = 0;
            for (k = 0; k < 3; k++) acc += R0[3 * i + k] * E[3 * k + j];
            R[3 * i + j] = acc;
        }
}

int main(void)
{
    const double pi = 3.14159265358979323846, L = 0.2, EI = 207e9 * pi * pow(0.8e-3, 4) / 64;
    const double I3[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    double worst = 0.0;
    unsigned seed = 12345u;
    int kirch, trial;
    gsl_set_error_handler_off();
    for (kirch = 0; kirch < 2; kirch++) {
        double rod[6], loads[7] = {0}, dist[3] = {0, 0, 0}, td[3 * TR_TD_NCOL];
        char msg[TR_MSGLEN];
        tr_options o = tr_default_options();
        tr_model *m = NULL;
        const int nb = kirch ? 3 : 6, n = 2 * nb;
        int i;
        rod[TR_ROD_L] = L, rod[TR_ROD_EI] = EI, rod[TR_ROD_GJ] = EI / 1.3;
        rod[TR_ROD_EA] = 1e7 * EI / (L * L), rod[TR_ROD_GA] = rod[TR_ROD_EA] / 2.6;
        rod[TR_ROD_KIRCHHOFF] = kirch;
        loads[TR_LD_S] = L;
        for (i = 0; i < 3; i++) {
            double *t = td + i * TR_TD_NCOL;
            t[TR_TD_OFFSET] = 0.005, t[TR_TD_ANGLE] = 2 * pi * i / 3;
            t[TR_TD_SLOPE] = i == 2 ? 10.0 : 0.0, t[TR_TD_EA] = 2e3, t[TR_TD_END] = L;
            t[TR_TD_CONTROL] = TR_DISPLACEMENT, t[TR_TD_VALUE] = 0.001, t[TR_TD_PRETENSION] = 0;
        }
        if (tr_model_alloc(&m, rod, td, 3, loads, 1, dist, &o, msg, sizeof msg) != TR_OK) {
            fprintf(stderr, "model: %s\n", msg);
            return 1;
        }
        for (trial = 0; trial < 200; trial++) {
            double Ra[9], Rb[9], pa[3], pb[3], tau[3], gj[12], gh[12], Hj[144], Hh[144];
            double scale = 0, gscale = 0;
            tr_elem e;
            int p, q, c, clamped, only;
            memset(&e, 0, sizeof e);
            rand_rot(&seed, 3.0, I3, Ra);
            rand_rot(&seed, 0.3, Ra, Rb);
            e.m = m, e.cosserat = !kirch, e.h = 0.01 * (1 + 0.5 * urand(&seed));
            e.sa = 0.1 * (1 + urand(&seed)) * 0.9, e.sb = e.sa + e.h;
            if (e.sb > L) e.sa = L - e.h, e.sb = L;
            for (c = 0; c < 3; c++) {
                pa[c] = 0.1 * urand(&seed);
                pb[c] = pa[c] + e.h * (Ra[3 * c + 2] + 0.01 * urand(&seed));
                tau[c] = trial % 4 == 0 && c == 1 ? 0.0 : 5.0 * (1 + urand(&seed));
                e.F[c] = urand(&seed), e.vhat[c] = (c == 2) + 0.01 * urand(&seed);
            }
            e.Ra = Ra, e.Rb = Rb, e.pa = pa, e.pb = pb, e.tau = tau, e.seg = 0;
            e.sr = m->general ? m->seg_rod : m->rod_k;
            clamped = trial % 5 == 0;
            for (only = 0; only < 3; only++) {
                /* the tendon chords' gradients (the bordered columns) likewise */
                double gc[12], gmax = 0.0;
                tr_elem_chord_gradient(&e, nb, clamped, only, gc);
                for (p = 0; p < n; p++) {
                    tr_hd xa[TR_ELEM_NB], xb[TR_ELEM_NB];
                    for (c = 0; c < TR_ELEM_NB; c++) xa[c] = xb[c] = hd_c(0.0);
                    if (p < nb) xa[p].a = 1.0; else xb[p - nb].a = 1.0;
                    gh[p] = tr_elem_energy(&e, xa, xb, only).a;
                    gmax = fmax(gmax, fabs(gh[p]));
                }
                for (p = clamped ? nb : 0; p < n; p++)
                    if (!(fabs(gc[p] - gh[p]) <= 1e-12 * gmax)) {
                        fprintf(stderr, "chord %d gradient %d: %.17g vs %.17g\n", only, p, gc[p],
                                gh[p]);
                        return 1;
                    }
            }
            if (kirch) {
                /* the Kirchhoff element's Hessian with its chords' gradients from the same
                 * passes: the same Hessian, and the chords' gradients to round-off */
                double gk[6], Hk[36], gcs[3 * 6];
                tr_elem_hessian(&e, nb, clamped, gj, Hj);
                tr_elem_hessian_chords(&e, clamped, gk, Hk, gcs);
                for (p = 0; p < 36; p++)
                    if (Hk[p] != Hj[p] || (p < 6 && gk[p] != gj[p])) {
                        fprintf(stderr, "hessian with chords %d differs\n", p);
                        return 1;
                    }
                for (only = 0; only < 3; only++) {
                    double gc[6];
                    tr_elem_chord_gradient(&e, nb, clamped, only, gc);
                    for (p = 0; p < 6; p++)
                        if (!(fabs(gc[p] - gcs[6 * only + p]) <= 1e-14 * (1.0 + fabs(gc[p])))) {
                            fprintf(stderr, "chord %d from the Hessian's passes %d: %.17g vs %.17g\n",
                                    only, p, gcs[6 * only + p], gc[p]);
                            return 1;
                        }
                }
            }
            tr_elem_hessian(&e, nb, clamped, gj, Hj);
            for (p = 0; p < n; p++)
                for (q = 0; q < n; q++) {
                    tr_hd xa[TR_ELEM_NB], xb[TR_ELEM_NB], E;
                    for (c = 0; c < TR_ELEM_NB; c++) xa[c] = xb[c] = hd_c(0.0);
                    if (p < nb) xa[p].a = 1.0; else xb[p - nb].a = 1.0;
                    if (q < nb) xa[q].b += 1.0; else xb[q - nb].b += 1.0;
                    E = tr_elem_energy(&e, xa, xb, -1);
                    Hh[p * n + q] = E.c;
                    if (p == q) gh[p] = E.a;
                }
            for (p = 0; p < n * n; p++) scale = fmax(scale, fabs(Hh[p]));
            for (p = 0; p < n; p++) gscale = fmax(gscale, fabs(gh[p]));
            for (p = clamped ? nb : 0; p < n; p++) {
                if (!(fabs(gj[p] - gh[p]) <= 1e-12 * gscale)) {
                    fprintf(stderr, "gradient %d: %.17g vs %.17g\n", p, gj[p], gh[p]);
                    return 1;
                }
                for (q = clamped ? nb : 0; q < n; q++) {
                    const double r = fabs(Hj[p * n + q] - Hh[p * n + q]) / scale;
                    worst = fmax(worst, r);
                    if (!(r <= 1e-12)) {
                        fprintf(stderr, "kirchhoff %d trial %d entry %d %d: %.17g vs %.17g\n",
                                kirch, trial, p, q, Hj[p * n + q], Hh[p * n + q]);
                        return 1;
                    }
                }
            }
        }
        tr_model_free(m);
    }
    printf("ok %.3g\n", worst);
    return 0;
}
