/*
 * tr_switch.c -- stability at a taut/slack switch.  A displacement-controlled tendon
 * with neither tension nor slack resists only the perturbations that stretch it: with
 * g_i the gradient of its length, the second variation is
 *     E(x) = Q(x) + sum_i k_i max(g_i x, 0)^2 / 2
 * (an inextensible tendon: the constraint g_i x <= 0), a quadratic on each cone of signs
 * of the g_i x.  Testing the slack side alone (every such tendon dropped, tr_stability.c)
 * is sufficient for stability but not necessary: a straight rod beyond its Euler load
 * held by locked tendons around it is stable, since every bend stretches one of them.
 *
 * The minimum of E on the unit sphere (the test's norm M) lies in the relative interior
 * of one face of one cone: the tendons of a set T at g x = 0, those of S stretched, the
 * rest slackened; there it is an eigenvector of the smallest eigenvalue of the pencil
 * (Q + sum_S k g g^T, M) on {g_T x = 0}.  Every face is visited (3^a of them for a
 * tendons at the switch, a <= TR_SWITCH_MAX): the margin is the smallest eigenvalue
 * whose eigenvectors reach into the interior of their face.  A cluster of more than two
 * eigenvalues at the bottom of a face leaves the verdict undecided.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "tendonrod.h"
#include "tr_internal.h"
#include "tr_stab.h"

int tr_switch_count(const tr_model *m_, const tr_data *d)
{
    const tr_model *m = TR_IN(m_, d);
    int i, a = 0;
    for (i = 0; i < m->nt; i++)
        a += m->tendon[i].control == TR_DISPLACEMENT && d->tau[i] == 0.0 && d->beta[i] == 0.0;
    return a;
}

/* x = (K - sigma M)^-1 x on the bordered space, with the factors of the last count:
 * x0 = A^-1 x, then mu from the Schur complement S = -C - B^T X (its eigen
 * decomposition Se, Sv), x = x0 - X mu. */
static void bordered_solve(tr_btd *h, double *x)
{
    const int n = h->nblk * h->nb, nb = h->nbord;
    double t[64], u[64];
    int r, c, q;
    tr_btd_solve(h, x, 1);
    if (nb <= 0 || nb > 64) return;
    for (r = 0; r < nb; r++) {
        double acc = 0.0;
        for (q = 0; q < n; q++) acc += h->B[q * nb + r] * x[q];
        t[r] = acc;
    }
    for (c = 0; c < nb; c++) {
        double acc = 0.0;
        for (r = 0; r < nb; r++) acc += h->Sv[r * nb + c] * t[r];
        u[c] = acc / h->Se[c];
    }
    for (r = 0; r < nb; r++) {
        double acc = 0.0;
        for (c = 0; c < nb; c++) acc += h->Sv[r * nb + c] * u[c];
        t[r] = -acc; /* mu = -S^-1 B^T x0 */
    }
    for (q = 0; q < n; q++) {
        double acc = 0.0;
        for (r = 0; r < nb; r++) acc += h->X[q * nb + r] * t[r];
        x[q] -= acc;
    }
}

/* M-orthonormalise the p columns V (n each, stored one after the other); 0 when one
 * vanishes. */
static int orthonormal(const tr_btd *h, double *V, int n, int p)
{
    int j, k, q;
    for (j = 0; j < p; j++) {
        double *v = V + (size_t)j * n, nrm = 0.0;
        for (k = 0; k < j; k++) {
            const double *u = V + (size_t)k * n;
            double dot = 0.0;
            for (q = 0; q < n; q++) dot += (h->Mw[q] + 1e-12) * u[q] * v[q];
            for (q = 0; q < n; q++) v[q] -= dot * u[q];
        }
        for (q = 0; q < n; q++) nrm += (h->Mw[q] + 1e-12) * v[q] * v[q];
        if (!(nrm > 0.0) || !isfinite(nrm)) return 0;
        nrm = 1.0 / sqrt(nrm);
        for (q = 0; q < n; q++) v[q] *= nrm;
    }
    return 1;
}

/* Is some combination c of the p (<= 2) columns of the face's eigenvectors strictly
 * inside the face: h_i . c > 0 for the rows h (na x p) of the signed g_i V?  By Gordan's
 * theorem, exactly when 0 is not in the convex hull of the h_i; then its point nearest
 * to 0 is such a c (with a margin checked against TR_SWITCH_INSIDE). */
static int inside(const double *hrow, const double *hn, int na, int p)
{
    double best[2] = {0.0, 0.0}, bn = INFINITY;
    int i, j, ok;
    if (na == 0) return 1;
    if (p == 1) {
        for (i = 0; i < na; i++)
            if (!(hrow[i] > TR_SWITCH_INSIDE * hn[i])) break;
        if (i == na) return 1;
        for (i = 0; i < na; i++)
            if (!(-hrow[i] > TR_SWITCH_INSIDE * hn[i])) return 0;
        return 1;
    }
    /* p == 2: the nearest point of the hull among the vertices and the segments */
    for (i = 0; i < na; i++)
        for (j = i; j < na; j++) {
            const double *a = hrow + 2 * i, *b = hrow + 2 * j;
            const double d0 = b[0] - a[0], d1 = b[1] - a[1], dd = d0 * d0 + d1 * d1;
            double t = dd > 0.0 ? -(a[0] * d0 + a[1] * d1) / dd : 0.0, c0, c1;
            t = t < 0.0 ? 0.0 : t > 1.0 ? 1.0 : t;
            c0 = a[0] + t * d0, c1 = a[1] + t * d1;
            if (c0 * c0 + c1 * c1 < bn) {
                /* the hull's nearest point: no vertex below the line through it */
                int k;
                for (ok = 1, k = 0; k < na && ok; k++)
                    ok = hrow[2 * k] * c0 + hrow[2 * k + 1] * c1 >=
                         (c0 * c0 + c1 * c1) * (1.0 - 1e-12);
                if (ok) bn = c0 * c0 + c1 * c1, best[0] = c0, best[1] = c1;
            }
        }
    if (!(bn < INFINITY) || !(bn > 0.0)) return 0;
    for (i = 0; i < na; i++)
        if (!(hrow[2 * i] * best[0] + hrow[2 * i + 1] * best[1] >
              TR_SWITCH_INSIDE * hn[i] * sqrt(bn)))
            return 0;
    return 1;
}

/* The constraints of a face (state 2) whose gradients depend on the others' (opposing
 * tendons on a straight rod: g_1 = -g_0) are dropped from the border, as the subspace
 * {g_T x = 0} is the same without them: a column that is (to 1e-9) a combination of the
 * earlier kept ones gets the slack tendon's zero column.  Gram-Schmidt on copies in the
 * scratch after the columns and the eigenvectors. */
static void drop_dependent(tr_btd *h, struct tr_stab_ws *w, const int *A, int a, const int *state,
                           int n)
{
    double *Q = w->sw_buf + (size_t)6 * n; /* room for TR_SWITCH_MAX basis columns */
    double *basis[TR_SWITCH_MAX];
    int i, k, q, nk = 0;
    for (i = 0; i < a; i++) {
        const int c = w->col[A[i]];
        double *v, n0 = 0.0, n1 = 0.0;
        if (state[i] != 2) continue;
        v = Q + (size_t)nk * n;
        for (q = 0; q < n; q++) v[q] = h->B[q * h->nbord + c], n0 += v[q] * v[q];
        for (k = 0; k < nk; k++) {
            double dot = 0.0;
            for (q = 0; q < n; q++) dot += basis[k][q] * v[q];
            for (q = 0; q < n; q++) v[q] -= dot * basis[k][q];
        }
        for (q = 0; q < n; q++) n1 += v[q] * v[q];
        if (!(n1 > 1e-18 * n0)) {
            for (q = 0; q < n; q++) h->B[q * h->nbord + c] = 0.0;
            h->cb[c] = 1.0;
            continue;
        }
        n1 = 1.0 / sqrt(n1);
        for (q = 0; q < n; q++) v[q] *= n1;
        basis[nk++] = v;
    }
}

/* The smallest eigenvalue whose eigenvectors reach into some face, over every face of
 * the level (nodes w->node[0..nn-1], assembled with the switch tendons bordered); NAN
 * and *undecided set where a face's bottom cluster has more than two eigenvalues or a
 * count is singular. */
static double faces_margin(const tr_model *m, struct tr_stab_ws *w, int nn, const int *A, int a,
                           int *face_S, int *face_T, int *undecided)
{
    tr_btd *h = &w->h;
    const int n = (nn - 1) * w->nb, nbord = h->nbord;
    double *G = w->sw_buf, *V = G + (size_t)4 * n, cb[TR_SWITCH_MAX];
    double best = INFINITY, hrow[2 * TR_SWITCH_MAX], hn[TR_SWITCH_MAX];
    int i, q, f, nf = 1, sing;
    for (i = 0; i < a; i++) nf *= 3;
    /* the switch tendons' columns and compliances, kept aside */
    for (i = 0; i < a; i++) {
        const int c = w->col[A[i]];
        for (q = 0; q < n; q++) G[(size_t)i * n + q] = h->B[q * nbord + c];
        cb[i] = h->cb[c];
    }
    for (f = 0; f < nf; f++) {
        int state[TR_SWITCH_MAX], code = f, neg, p, s, na = 0, skip = 0;
        double lam, sig, eta;
        for (i = 0; i < a; i++) state[i] = code % 3, code /= 3; /* 0 slack, 1 S, 2 T */
        for (i = 0; i < a; i++) {
            const int c = w->col[A[i]];
            /* an inextensible tendon cannot be stretched: no S side */
            if (state[i] == 1 && !(cb[i] > 0.0)) skip = 1;
            for (q = 0; q < n; q++) h->B[q * nbord + c] = state[i] ? G[(size_t)i * n + q] : 0.0;
            /* a slack tendon's column: zero, its compliance 1 (a decoupled pivot -1 that
             * the count's one-per-column cancels) */
            h->cb[c] = state[i] == 2 ? 0.0 : state[i] == 1 ? cb[i] : 1.0;
        }
        drop_dependent(h, w, A, a, state, n);
        if (skip) continue;
        neg = tr_btd_count(h, 0.0, &sing);
        if (sing) neg = tr_btd_count(h, -1e-9, &sing);
        if (sing) {
            *undecided = 1;
            continue;
        }
        lam = tr_btd_smallest(h, neg > 0);
        if (!(lam < best)) continue; /* cannot lower the margin */
        eta = TR_SWITCH_CLUSTER * (1.0 + fabs(lam));
        sig = lam - 0.1 * eta;
        p = tr_btd_count(h, lam + eta, &sing);
        s = tr_btd_count(h, sig, &sing);
        if (sing) {
            *undecided = 1;
            continue;
        }
        p -= s;
        if (p < 1) p = 1;
        if (p > 2) {
            *undecided = 1;
            continue;
        }
        /* inverse iteration at sig (factored by the last count) on p vectors */
        for (s = 0; s < p; s++)
            for (q = 0; q < n; q++)
                V[(size_t)s * n + q] = 1.0 + 0.5 * sin(1.7 * (q + 1) * (s + 1)) + (s ? q % 2 : 0);
        for (i = 0; i < TR_SWITCH_SWEEPS; i++) {
            for (s = 0; s < p; s++) {
                double *v = V + (size_t)s * n;
                for (q = 0; q < n; q++) v[q] *= h->Mw[q] + 1e-12;
                bordered_solve(h, v);
            }
            if (!orthonormal(h, V, n, p)) break;
        }
        if (i < TR_SWITCH_SWEEPS) {
            *undecided = 1;
            continue;
        }
        for (i = 0; i < a; i++) {
            double g2 = 0.0;
            if (state[i] == 2) continue;
            for (q = 0; q < n; q++) g2 += G[(size_t)i * n + q] * G[(size_t)i * n + q];
            for (s = 0; s < p; s++) {
                double acc = 0.0;
                for (q = 0; q < n; q++) acc += G[(size_t)i * n + q] * V[(size_t)s * n + q];
                hrow[p * na + s] = (state[i] == 1 ? 1.0 : -1.0) * acc;
            }
            /* |g| |x| with |x| measured like the columns (M-unit, Euclidean scale) */
            {
                double vv = 0.0;
                for (q = 0; q < n; q++) vv += V[q] * V[q];
                hn[na] = sqrt(g2 * vv);
            }
            na++;
        }
        if (inside(hrow, hn, na, p)) {
            best = lam;
            *face_S = *face_T = 0;
            for (i = 0; i < a; i++) {
                if (state[i] == 1) *face_S |= 1 << i;
                if (state[i] == 2) *face_T |= 1 << i;
            }
        }
    }
    /* the columns as assembled */
    for (i = 0; i < a; i++) {
        const int c = w->col[A[i]];
        for (q = 0; q < n; q++) h->B[q * nbord + c] = G[(size_t)i * n + q];
        h->cb[c] = cb[i];
    }
    return best < INFINITY ? best : NAN;
}

/* The margin of one level (grid nodes of kind >= min_kind) with the switch tendons. */
static double level(const tr_model *m, const tr_data *d, struct tr_stab_ws *w, int min_kind,
                    const int *A, int a, int *fS, int *fT, int *undecided)
{
    int nn = 0, j;
    unsigned long long mask = 0;
    for (j = 0; j < w->ngrid; j++)
        if (w->kind[j] >= min_kind) w->node[nn++] = j;
    w->sw_mask = 0;
    if (tr_stab_level_setup(m, d, w, nn) < 0) {
        *undecided = 1;
        return NAN;
    }
    tr_stab_assemble(m, w, nn, w->nb);
    tr_stab_discrete_equilibrium(m, w, nn, w->nb);
    for (j = 0; j < a; j++) mask |= 1ULL << A[j];
    w->sw_mask = mask;
    tr_stab_assemble(m, w, nn, w->nb);
    w->sw_mask = 0;
    return faces_margin(m, w, nn, A, a, fS, fT, undecided);
}

static void list_tendons(char *buf, size_t len, const int *A, int a, int set)
{
    int i, first = 1;
    buf[0] = '\0';
    for (i = 0; i < a; i++)
        if (set >> i & 1) {
            const size_t l = strlen(buf);
            snprintf(buf + l, len - l, first ? "%d" : ", %d", A[i]);
            first = 0;
        }
    if (first) snprintf(buf, len, "none");
}

void tr_switch_verdict(const tr_model *m_, tr_data *d)
{
    const tr_model *m = TR_IN(m_, d);
    int A[TR_SWITCH_MAX], a = 0, i, fS = 0, fT = 0, und = 0, cS, cT;
    double mf, mc, err;
    struct tr_stab_ws *w;
    char sl[64], tl[64], kl[64];
    if (d->stable != 0) return;
    for (i = 0; i < m->nt; i++)
        if (m->tendon[i].control == TR_DISPLACEMENT && d->tau[i] == 0.0 && d->beta[i] == 0.0) {
            if (a == TR_SWITCH_MAX || i >= 64) {
                d->stable = -1;
                snprintf(d->stab_reason, sizeof d->stab_reason,
                         "not decided: unstable on the slack side of more than %d tendons at "
                         "their taut/slack switch, which are not tested side by side",
                         TR_SWITCH_MAX);
                return;
            }
            A[a++] = i;
        }
    if (a == 0) return;
    w = tr_stab_workspace(m, d, &d->stab, d->stab ? d->stab->nuni : TR_STAB_ELEMENTS, 0);
    if (!w || tr_record_from(m, w->rec, d->x, d->steps) != TR_OK) return;
    mf = level(m, d, w, 0, A, a, &fS, &fT, &und);
    mc = mf;
    err = 0.0;
    if (isfinite(mf) && fabs(mf) < TR_STAB_CHECK * (1.0 + tr_stiffness_scale(m, d))) {
        /* near zero: the discretisation error from half the elements, as the full test */
        mc = level(m, d, w, 1, A, a, &cS, &cT, &und);
        err = fabs(mf - mc) / 3.0;
    }
    d->stab_gap = 0.0; /* a switch's verdict is not carried */
    list_tendons(sl, sizeof sl, A, a, (1 << a) - 1);
    if (!isfinite(mf) || (und && !(mf < -2.0 * err))) {
        d->stable = -1;
        snprintf(d->stab_reason, sizeof d->stab_reason,
                 "not decided: unstable on the slack side of tendons %s at their taut/slack "
                 "switch, and the test of the sides they resist could not be completed",
                 sl);
        return;
    }
    d->stability = mf;
    if (fabs(mf) <= 2.0 * err || fabs(mf) <= TR_STAB_NEUTRAL) {
        d->stable = -1;
        snprintf(d->stab_reason, sizeof d->stab_reason,
                 "critical within the accuracy of the test: margin %.3g EI/L with tendons %s "
                 "at their taut/slack switch (discretisation error about %.2g)",
                 mf, sl, err);
        return;
    }
    d->stable = mf > 0.0;
    d->stab_index = mf > 0.0 ? 0 : 1;
    if (mf > 0.0) {
        snprintf(d->stab_reason, sizeof d->stab_reason,
                 "stable: margin %.4g EI/L; tendons %s are at their taut/slack switch and "
                 "every direction that lowers the energy with them slack stretches one of them",
                 mf, sl);
    } else {
        list_tendons(sl, sizeof sl, A, a, fS);
        list_tendons(tl, sizeof tl, A, a, ~(fS | fT) & ((1 << a) - 1));
        list_tendons(kl, sizeof kl, A, a, fT);
        snprintf(d->stab_reason, sizeof d->stab_reason,
                 "unstable: margin %.4g EI/L along a direction that, of the tendons at their "
                 "taut/slack switch, stretches %s, slackens %s and keeps %s at their length",
                 mf, sl, tl, kl);
    }
}
