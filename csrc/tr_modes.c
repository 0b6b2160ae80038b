/*
 * tr_modes.c -- natural frequencies and mode shapes of small vibrations about a solved
 * equilibrium (tr_modes.h).
 *
 * Stiffness: the second variation of the total potential energy that the stability
 * verdict assembles (tr_stab_energy.c) -- rod strain energy, the tension-held tendons as
 * constant forces, the displacement-held ones as bordered constraints or springs EA/l,
 * the dead loads -- on Cosserat elements (rotation and position perturbations at every
 * node, so that the translational mass is diagonal), at the recorded solution (not
 * moved to each grid's discrete equilibrium: its O(h^2) gradient moves the Hessian by a
 * smooth O(h^2) that the extrapolation removes; measured on a bent three-tendon robot,
 * the frequencies with and without those Newton steps agree to 1e-8, at a third of the
 * cost).  Slack tendons stay slack.  Mass: lumped at the nodes with trapezoid weights,
 * rho A on the positions and rho (I1, I2, J) on the body-frame rotations, point masses
 * on the positions of their nodes (their arc lengths are nodes of every grid).
 *
 * Eigenvalues of the bordered pencil (H, M): subspace iteration on (H - sigma M)^-1 M
 * with the block LDL^T of tr_inertia.c (sigma below the lowest eigenvalue, found by its
 * Sturm count), Rayleigh-Ritz on the iterates, and a Sturm check that no eigenvalue below
 * the n-th Ritz value was missed.  On grids of N, 2N, 4N ... elements (each piece between
 * breakpoints uniform, halved from grid to grid) the eigenvalues are second order in the
 * element length with an even expansion (midpoint elements, trapezoid mass), so Richardson
 * extrapolation applies; the difference of the last two extrapolations is the accuracy
 * estimate, and where the ratio of successive grid differences is not near 4 (outside the
 * asymptotic range) the finest grid's difference is.
 */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <gsl/gsl_eigen.h>
#include <gsl/gsl_errno.h>

#include "tendonrod.h"
#include "tr_internal.h"
#include "tr_modes.h"
#include "tr_stab.h"

/* ------------------------------------------------------------ contact with the model
 * The few places that read or copy tr_model / tr_data fields (L, EI, kirchhoff, the
 * rigidity rows, the breakpoints; the workspace's state and tensions). */

/* The model the elements see: m itself, or for a Kirchhoff rod a shallow copy whose
 * rigidity rows carry the shear and axial penalty TR_MODES_PENALTY EI / h^2. */
static const tr_model *element_model(const tr_model *m, tr_model *mm, double *rows, double h)
{
    int k;
    if (!m->kirchhoff) return m;
    *mm = *m;
    for (k = 0; k < (m->general ? m->nseg : 1); k++) {
        double *r = m->general ? rows + (size_t)TR_SR_NCOL * k : mm->rod_k;
        if (m->general) memcpy(r, m->seg_rod + (size_t)TR_SR_NCOL * k, TR_SR_NCOL * sizeof(double));
        r[TR_SR_EA] = r[TR_SR_GA] = TR_MODES_PENALTY * r[TR_SR_EI] / (h * h);
    }
    if (m->general) mm->seg_rod = rows;
    return mm;
}

/* The workspace at the solution x: counters reset, tensions set. */
static void at_solution(const tr_model *m, tr_data *d, const double *x, int steps)
{
    tr_solve_reset(m, d, steps);
    memcpy(d->x, x, (size_t)d->k * sizeof(double));
    tr_set_tensions(m, d, d->x);
}

/* ------------------------------------------------------------ the grids */
typedef struct {
    int nlev, nfine, n, p, nv; /* grids; nodes of the finest; modes; subspace; max unknowns */
    int *lev;                  /* (nfine) the coarsest grid holding each node */
    int *idx;                  /* (nfine) scratch: a node's block on a grid (-1: base) */
    struct tr_stab_ws w;       /* the verdict's level workspace on the finest grid */
    double *X, *Y, *Z, *T, *K, *Mp, *C, *th, *th_old, *lam; /* subspace iteration */
    double lmax; /* the finest grid's largest_bound [rad^2/s^2] */
    gsl_eigen_gensymmv_workspace *gw;
    gsl_matrix_view Kv, Mv, Cv;
    gsl_vector_view thv;
} modes_ws;

/* The breakpoints of the grids: the model's and the point masses' arc lengths, sorted,
 * merged within 1e-12 L, into gb (cap entries); returns their count - 1 (pieces). */
static int grid_breaks(const tr_model *m, const tr_modes_spec *sp, double *gb)
{
    int n = 0, i, j;
    for (i = 0; i <= m->nseg; i++) gb[n++] = m->bp[i];
    for (i = 0; i < sp->npm; i++)
        if (sp->pm[2 * i] > 0.0 && sp->pm[2 * i] < m->L) gb[n++] = sp->pm[2 * i];
    for (i = 1; i < n; i++) /* insertion sort: few entries */
        for (j = i; j > 0 && gb[j - 1] > gb[j]; j--) {
            const double t = gb[j];
            gb[j] = gb[j - 1], gb[j - 1] = t;
        }
    for (i = j = 1; i < n; i++)
        if (gb[i] > gb[j - 1] + 1e-12 * m->L) gb[j++] = gb[i];
    gb[j - 1] = m->L;
    return j - 1;
}

/* Elements of piece k on the coarsest grid. */
static int piece_elements(const tr_model *m, const double *gb, int k, int nel)
{
    const long e = lround(nel * (gb[k + 1] - gb[k]) / m->L);
    return e < 1 ? 1 : (int)e;
}

static void ws_free(modes_ws *s)
{
    if (s->gw) gsl_eigen_gensymmv_free(s->gw);
    tr_data_free(s->w.rec);
    free(s->w.s);
    free(s->lev);
    free(s->w.R);
    free(s->X);
    memset(s, 0, sizeof *s);
}

/* The finest grid's nodes and every buffer, once per call.  0 or -1 (out of memory).
 * The verdict's level workspace is carved by tr_stab_layout as the verdict's is, on this
 * grid (piecewise uniform between breakpoints and point masses, so that every element
 * halves from grid to grid) instead of the verdict's uniform one. */
static int ws_alloc(const tr_model *m, tr_data *d, const tr_modes_spec *sp, int nel, double *gb,
                    modes_ws *s)
{
    const int nlev = sp->levels > 0 ? sp->levels : TR_MODES_LEVELS;
    const int np = grid_breaks(m, sp, gb), nt = m->nt > 0 ? m->nt : 1, nb = 6;
    int cap = 1, k, i, l, j = 0;
    size_t nv, pp;
    double *q;
    char msg[TR_MSGLEN];
    tr_options o = d->opt;
    struct tr_stab_ws *w = &s->w;
    memset(s, 0, sizeof *s);
    for (k = 0; k < np; k++) cap += piece_elements(m, gb, k, nel) << (nlev - 1);
    s->nlev = nlev, s->nfine = cap, s->n = sp->n;
    nv = (size_t)(cap - 1) * nb;
    s->nv = (int)nv;
    s->p = sp->n + (sp->n > TR_MODES_GUARD ? sp->n : TR_MODES_GUARD);
    if (s->p > s->nv) s->p = s->nv;
    pp = (size_t)s->p;
    w->nuni = nel, w->nb = nb, w->cosserat = 1;
    w->s = (double *)malloc((size_t)cap * sizeof(double));
    s->lev = (int *)malloc(((size_t)cap * 3 + nt) * sizeof(int));
    w->R = (double *)malloc(tr_stab_len((size_t)cap, (size_t)nb, (size_t)nt) * sizeof(double));
    s->X =
        (double *)malloc((3 * nv * pp + 3 * pp * pp + 3 * pp + (size_t)nlev * pp) * sizeof(double));
    s->gw = gsl_eigen_gensymmv_alloc(pp);
    if (!w->s || !s->lev || !w->R || !s->X || !s->gw) return -1;
    s->idx = s->lev + cap;
    w->kind = s->idx; /* the layout's kinds are modes' indices; its nodes and columns follow */
    tr_stab_layout(m, w, (size_t)cap);
    q = s->X;
    s->Y = q + nv * pp, s->Z = q + 2 * nv * pp, q += 3 * nv * pp;
    s->K = q, s->Mp = q + pp * pp, s->C = q + 2 * pp * pp, q += 3 * pp * pp;
    s->th = q, s->th_old = q + pp, s->T = q + 2 * pp, q += 3 * pp;
    s->lam = q;
    s->Kv = gsl_matrix_view_array(s->K, pp, pp);
    s->Mv = gsl_matrix_view_array(s->Mp, pp, pp);
    s->Cv = gsl_matrix_view_array(s->C, pp, pp);
    s->thv = gsl_vector_view_array(s->th, pp);
    /* the nodes: each piece uniform, its first node on every grid */
    for (k = 0; k < np; k++) {
        const int ne = piece_elements(m, gb, k, nel) << (nlev - 1);
        for (i = 0; i < ne; i++, j++) {
            w->s[j] = i == 0 ? gb[k] : gb[k] + (gb[k + 1] - gb[k]) * i / ne;
            for (l = 0; l < nlev && i % (1 << (nlev - 1 - l)) != 0; l++) {}
            s->lev[j] = l;
        }
    }
    w->s[j] = m->L, s->lev[j] = 0;
    w->ngrid = cap;
    o.tip_only = 0;
    w->rec = tr_data_alloc(m, &o, cap, w->s, msg, sizeof msg);
    return w->rec ? 0 : -1;
}

/* ------------------------------------------------------------ the pencil of a grid */
/* The nodes of grid l into w->node (their count), and each node's block (idx). */
static int grid_nodes(modes_ws *s, int l)
{
    int j, nn = 0;
    for (j = 0; j < s->nfine; j++) {
        s->idx[j] = -1;
        if (s->lev[j] <= l) s->idx[j] = nn - 1, s->w.node[nn++] = j;
    }
    return nn;
}

/* The section row of mass at arc length s. */
static const double *mass_row(const tr_modes_spec *sp, double s)
{
    int k = 0;
    while (k + 1 < sp->nmass && sp->mass[5 * k] <= s) k++;
    return sp->mass + 5 * k;
}

/* The lumped mass of the grid's nodes into w->h.Mw (node j >= 1 is block j - 1). */
static void lumped_mass(const tr_modes_spec *sp, modes_ws *s, int nn)
{
    struct tr_stab_ws *w = &s->w;
    int j, c, i;
    for (i = 0; i < (nn - 1) * 6; i++) w->h.Mw[i] = 0.0;
    for (j = 0; j + 1 < nn; j++) {
        const double sa = w->s[w->node[j]], sb = w->s[w->node[j + 1]], h = sb - sa;
        const double *r = mass_row(sp, 0.5 * (sa + sb));
        for (c = 0; c < 6; c++) {
            const double mc = c < 3 ? (sp->rotary ? r[2 + c] : 0.0) : r[1];
            if (j > 0) w->h.Mw[(j - 1) * 6 + c] += 0.5 * h * mc;
            w->h.Mw[j * 6 + c] += 0.5 * h * mc;
        }
    }
    for (i = 0; i < sp->npm; i++)
        for (j = 1; j < nn; j++)
            if (fabs(w->s[w->node[j]] - sp->pm[2 * i]) <= 1e-12 * w->s[w->node[nn - 1]])
                for (c = 3; c < 6; c++) w->h.Mw[(j - 1) * 6 + c] += sp->pm[2 * i + 1];
}

/* Y = (H - sigma M)^-1 (the bordered pencil's) Y, p columns, with the factors of the
 * last tr_btd_count: y0 = A^-1 y, mu = -S^-1 B^T y0, y = y0 - A^-1 B mu. */
static void bordered_solve(tr_btd *h, double *Y, int p, double *T)
{
    const int n = h->nblk * h->nb, nbord = h->nbord;
    int r, c, q, col;
    tr_btd_solve(h, Y, p);
    for (col = 0; col < p && nbord > 0; col++) {
        double t[64], u[64];
        for (r = 0; r < nbord; r++) {
            double acc = 0.0;
            for (q = 0; q < n; q++) acc += h->B[q * nbord + r] * Y[(size_t)q * p + col];
            t[r] = acc;
        }
        /* u = -Sv diag(1/Se) Sv^T t */
        for (r = 0; r < nbord; r++) {
            double acc = 0.0;
            for (q = 0; q < nbord; q++) acc += h->Sv[q * nbord + r] * t[q];
            T[r] = acc / h->Se[r];
        }
        for (r = 0; r < nbord; r++) {
            double acc = 0.0;
            for (q = 0; q < nbord; q++) acc += h->Sv[r * nbord + q] * T[q];
            u[r] = -acc;
        }
        for (q = 0; q < n; q++) {
            double acc = 0.0;
            for (c = 0; c < nbord; c++) acc += h->X[q * nbord + c] * u[c];
            Y[(size_t)q * p + col] -= acc;
        }
    }
}

/* Gershgorin's bound on the largest eigenvalue of the grid's pencil: the rows of
 * M^-1/2 H M^-1/2 over the coordinates with a mass.  The scale of the round-off in the
 * eigenvalues (eps times it). */
static double largest_bound(const tr_btd *h)
{
    const int nb = h->nb, nb2 = nb * nb;
    const double *Mw = h->Mw;
    double g = 0.0;
    int j, r, c;
    for (j = 0; j < h->nblk; j++)
        for (r = 0; r < nb; r++) {
            const double mr = Mw[j * nb + r];
            double rad = 0.0;
            if (!(mr > 0.0)) continue;
            for (c = 0; c < nb; c++) {
                if (Mw[j * nb + c] > 0.0)
                    rad += fabs(h->D[j * nb2 + r * nb + c]) / sqrt(Mw[j * nb + c]);
                if (j + 1 < h->nblk && Mw[(j + 1) * nb + c] > 0.0)
                    rad += fabs(h->E[j * nb2 + r * nb + c]) / sqrt(Mw[(j + 1) * nb + c]);
                if (j > 0 && Mw[(j - 1) * nb + c] > 0.0)
                    rad += fabs(h->E[(j - 1) * nb2 + c * nb + r]) / sqrt(Mw[(j - 1) * nb + c]);
            }
            g = fmax(g, rad / sqrt(mr));
        }
    return g;
}

/* A shift below the pencil's lowest eigenvalue (count 0, no singular pivot), from
 * -1e-3 lref down by quadrupling; NAN when none is found. */
static double lowest_shift(tr_btd *h, double lref, int *nfac)
{
    double sig = -1e-3 * lref;
    int it, sing, cnt;
    for (it = 0; it < 60; it++, sig *= 4.0) {
        cnt = tr_btd_count(h, sig, &sing);
        ++*nfac;
        if (!sing && cnt == 0) return sig;
    }
    return NAN;
}

/* Subspace iteration on the grid's pencil from the start vectors in s->X (nv x p):
 * the p Ritz values into s->th (ascending), vectors in s->X (M-normalised).  TR_OK,
 * TR_ESINGULAR (no shift, or the Sturm check failed), or the poll's stop. */
static int grid_eigen(tr_data *d, modes_ws *s, int nn, double lref, double lmax, int *nit,
                      int *nfac)
{
    tr_btd *h = &s->w.h;
    const int nv = (nn - 1) * 6, p = s->p, n = s->n;
    const double *Mw = h->Mw;
    /* the Ritz values settle to their round-off, not below */
    const double floor_ = TR_MODES_STURM_ROUNDOFF * DBL_EPSILON * lmax;
    double sig;
    int it, i, j, c, sing, cnt, st;
    sig = lowest_shift(h, lref, nfac);
    if (!isfinite(sig)) return TR_ESINGULAR;
    for (i = 0; i < p; i++) s->th_old[i] = INFINITY;
    for (it = 0; it < TR_MODES_SWEEPS; it++) {
        double change = 0.0;
        if ((st = tr_poll(d)) != TR_OK) return st;
        ++*nit;
        /* Z = M X; Y = A^-1 Z */
        for (i = 0; i < nv; i++)
            for (c = 0; c < p; c++) s->Z[(size_t)i * p + c] = Mw[i] * s->X[(size_t)i * p + c];
        memcpy(s->Y, s->Z, (size_t)nv * p * sizeof(double));
        bordered_solve(h, s->Y, p, s->T);
        /* Kp = Y^T M X + sig Y^T M Y, Mp = Y^T M Y */
        for (i = 0; i < p; i++)
            for (j = i; j < p; j++) {
                double ky = 0.0, my = 0.0;
                int q;
                for (q = 0; q < nv; q++) {
                    const double yi = s->Y[(size_t)q * p + i], yj = s->Y[(size_t)q * p + j];
                    ky += 0.5 * (yi * s->Z[(size_t)q * p + j] + yj * s->Z[(size_t)q * p + i]);
                    my += yi * Mw[q] * yj;
                }
                s->K[i * p + j] = s->K[j * p + i] = ky + sig * my;
                s->Mp[i * p + j] = s->Mp[j * p + i] = my;
            }
        if (gsl_eigen_gensymmv(&s->Kv.matrix, &s->Mv.matrix, &s->thv.vector, &s->Cv.matrix,
                               s->gw) != GSL_SUCCESS)
            return TR_ESINGULAR;
        gsl_eigen_gensymmv_sort(&s->thv.vector, &s->Cv.matrix, GSL_EIGEN_SORT_VAL_ASC);
        /* X = Y C, M-normalised */
        for (c = 0; c < p; c++) {
            double nm = 0.0;
            for (i = 0; i < nv; i++) {
                double acc = 0.0;
                for (j = 0; j < p; j++) acc += s->Y[(size_t)i * p + j] * s->C[j * p + c];
                s->X[(size_t)i * p + c] = acc;
                nm += acc * acc * Mw[i];
            }
            nm = nm > 0.0 ? 1.0 / sqrt(nm) : 1.0;
            for (i = 0; i < nv; i++) s->X[(size_t)i * p + c] *= nm;
        }
        for (i = 0; i < n; i++)
            change = fmax(change, fabs(s->th[i] - s->th_old[i]) /
                                      fmax(fabs(s->th[i] - sig), floor_ / TR_MODES_RITZ_TOL));
        if (!(change > TR_MODES_RITZ_TOL)) break;
        memcpy(s->th_old, s->th, (size_t)p * sizeof(double));
    }
    /* the Sturm check: no eigenvalue missed below the n-th Ritz value */
    cnt = tr_btd_count(h,
                       s->th[n - 1] - fmax(TR_MODES_STURM * fabs(s->th[n - 1] - sig),
                                           TR_MODES_STURM_ROUNDOFF * DBL_EPSILON * lmax),
                       &sing);
    ++*nfac;
    if (!sing && cnt > n - 1) return TR_ESINGULAR;
    return TR_OK;
}

/* Start vectors of the coarsest grid: deterministic pseudo-random entries. */
static void start_vectors(modes_ws *s, int nv)
{
    unsigned long long r = 88172645463325252ULL;
    int i;
    for (i = 0; i < nv * s->p; i++) {
        r ^= r << 13, r ^= r >> 7, r ^= r << 17;
        s->X[i] = (double)(r >> 11) / 9007199254740992.0 - 0.5;
    }
}

/* The vectors of grid l - 1 (blocks in idx as grid_nodes(l - 1) left them, copied to
 * Z) onto grid l: shared nodes copied, new ones the mean of their neighbours. */
static void prolong(modes_ws *s, int l)
{
    const int p = s->p;
    int j, c, k = 0;
    for (j = 0; j < s->nfine; j++) s->idx[j] = s->lev[j] <= l - 1 ? s->idx[j] : -2;
    memcpy(s->Z, s->X, (size_t)s->nv * p * sizeof(double));
    for (j = 1; j < s->nfine; j++) {
        if (s->lev[j] > l) continue;
        k++; /* node j is block k - 1 on grid l */
        if (s->idx[j] >= 0) {
            for (c = 0; c < 6 * p; c++)
                s->X[(size_t)(k - 1) * 6 * p + c] = s->Z[(size_t)s->idx[j] * 6 * p + c];
        } else {
            int a = j - 1, b = j + 1;
            while (s->idx[a] == -2) a--;
            while (s->idx[b] == -2) b++;
            for (c = 0; c < 6 * p; c++)
                s->X[(size_t)(k - 1) * 6 * p + c] =
                    0.5 * ((s->idx[a] >= 0 ? s->Z[(size_t)s->idx[a] * 6 * p + c] : 0.0) +
                           s->Z[(size_t)s->idx[b] * 6 * p + c]);
        }
    }
}

/* ------------------------------------------------------------ results */
/* Richardson extrapolation of eigenvalue i over the grids, its accuracy estimate. */
static void extrapolate(const modes_ws *s, int i, double *val, double *err)
{
    const int L = s->nlev, n = s->n;
    double R[TR_MODES_MAX_LEVELS][TR_MODES_MAX_LEVELS] = {{0.0}};
    int l, k;
    for (l = 0; l < L; l++) {
        R[l][0] = s->lam[l * n + i];
        for (k = 1; k <= l; k++)
            R[l][k] = R[l][k - 1] + (R[l][k - 1] - R[l - 1][k - 1]) / (double)((1 << (2 * k)) - 1);
    }
    *val = R[L - 1][L - 1];
    if (L == 1) {
        *err = NAN;
        return;
    }
    *err = fabs(R[L - 1][L - 1] - R[L - 1][L - 2]);
    if (L >= 3) {
        const double d1 = R[L - 1][0] - R[L - 2][0], d0 = R[L - 2][0] - R[L - 3][0];
        const double tiny = 1e-12 * fabs(R[L - 1][0]);
        if (fabs(d1) > tiny &&
            !(fabs(d0 / d1 - 4.0) <= TR_MODES_RATIO_BAND)) /* not second order yet */
            *err = fmax(*err, fabs(d1));
    }
    *err += TR_MODES_ROUNDOFF * DBL_EPSILON * s->lmax;
}

/* The finest grid's shapes, normalised: the largest centre-line displacement |dp| over
 * the nodes is 1 m (a mode that moves the centre line by less than TR_MODES_TWIST of L
 * times its largest rotation, such as pure torsion: the largest L |dtheta| is), the
 * entry of largest magnitude positive; the modal mass x^T M x of that shape [kg]. */
static void shapes(const tr_model *m, const modes_ws *s, tr_modes_out *o)
{
    const struct tr_stab_ws *w = &s->w;
    const int ns = s->nfine, p = s->p;
    int i, j, c, r;
    for (j = 0; j < ns; j++) {
        o->s[j] = w->s[j];
        for (c = 0; c < 3; c++) o->pos0[3 * j + c] = w->rec->pos[3 * j + c];
    }
    for (i = 0; i < s->n; i++) {
        double *dp = o->dpos + (size_t)i * ns * 3, *dr = o->drot + (size_t)i * ns * 3;
        double ap = 0.0, ar = 0.0, bp = 0.0, br = 0.0, big, sc, mm = 0.0;
        for (c = 0; c < 3; c++) dp[c] = dr[c] = 0.0;
        for (j = 1; j < ns; j++) {
            const double *x = s->X + (size_t)(j - 1) * 6 * p;
            const double *R = w->R + 9 * j;
            for (r = 0; r < 3; r++) {
                double acc = 0.0;
                for (c = 0; c < 3; c++) acc += R[3 * r + c] * x[c * p + i];
                dr[3 * j + r] = acc;
                dp[3 * j + r] = x[(3 + r) * p + i];
                if (fabs(acc) > fabs(br)) br = acc;
                if (fabs(dp[3 * j + r]) > fabs(bp)) bp = dp[3 * j + r];
            }
            ap = fmax(ap, sqrt(dp[3 * j] * dp[3 * j] + dp[3 * j + 1] * dp[3 * j + 1] +
                               dp[3 * j + 2] * dp[3 * j + 2]));
            ar = fmax(ar, m->L * sqrt(dr[3 * j] * dr[3 * j] + dr[3 * j + 1] * dr[3 * j + 1] +
                                      dr[3 * j + 2] * dr[3 * j + 2]));
        }
        if (!(ap > TR_MODES_TWIST * ar)) ap = ar, bp = br;
        big = bp;
        sc = ap > 0.0 ? (big < 0.0 ? -1.0 : 1.0) / ap : 1.0;
        for (j = 0; j < 3 * ns; j++) dp[j] *= sc, dr[j] *= sc;
        for (j = 0; j < s->nv; j++)
            mm += s->X[(size_t)j * p + i] * s->X[(size_t)j * p + i] * w->h.Mw[j];
        o->modal_mass[i] = mm * sc * sc;
    }
}

/* ------------------------------------------------------------ the run */
static int check_spec(const tr_model *m, const tr_modes_spec *sp, char *msg, size_t len)
{
    int i;
    if (sp->n < 1 || sp->n > TR_MODES_MAX)
        return tr_msgf(msg, len, "n = %d: 1 to %d modes", sp->n, TR_MODES_MAX), TR_EINVAL;
    if (sp->elements != 0 && (sp->elements < 2 || sp->elements > TR_MODES_MAX_ELEMENTS))
        return tr_msgf(msg, len, "elements = %d: 2 to %d", sp->elements, TR_MODES_MAX_ELEMENTS),
               TR_EINVAL;
    if (sp->levels < 0 || sp->levels > TR_MODES_MAX_LEVELS)
        return tr_msgf(msg, len, "levels = %d: 1 to %d", sp->levels, TR_MODES_MAX_LEVELS),
               TR_EINVAL;
    if (sp->nmass < 1 || !sp->mass || sp->npm < 0 || sp->npm > 64)
        return tr_msgf(msg, len, "no mass table, or more than 64 point masses"), TR_EINVAL;
    for (i = 0; i < 5 * sp->nmass; i++)
        if (!(sp->mass[i] >= 0.0 && isfinite(sp->mass[i])))
            return tr_msgf(msg, len, "mass table entry %d = %g: finite and >= 0", i, sp->mass[i]),
                   TR_EINVAL;
    for (i = 0; i < sp->nmass; i++)
        if (!(sp->mass[5 * i + 1] > 0.0))
            return tr_msgf(msg, len, "the rod has no mass (rho A = %g kg/m): give Rod(density=)",
                           sp->mass[5 * i + 1]),
                   TR_EINVAL;
    for (i = 0; i < 2 * sp->npm; i++)
        if (!(sp->pm[i] >= 0.0 && isfinite(sp->pm[i]) && (i % 2 || sp->pm[i] <= m->L)))
            return tr_msgf(msg, len, "point mass entry %d = %g: finite, >= 0, s <= L", i,
                           sp->pm[i]),
                   TR_EINVAL;
    return TR_OK;
}

int tr_modes(const tr_model *m_, tr_data *d, const double *x, int steps, const tr_modes_spec *spec,
             tr_modes_out *o)
{
    const tr_model *m = TR_IN(m_, d); /* the workspace's values */
    modes_ws s;
    tr_modes_spec sp = *spec;
    tr_model mm;
    double *rows = NULL, *gb = NULL;
    double lref, lmax;
    int nel, st, l, i, nn = 0, nit = 0, nfac = 0;
    memset(o, 0, sizeof *o);
    memset(&s, 0, sizeof s);
    if ((st = check_spec(m, &sp, o->message, sizeof o->message)) != TR_OK) return st;
    if (sp.levels == 0) sp.levels = TR_MODES_LEVELS;
    /* the scale of the pencil's eigenvalues (L/EI) omega^2: omega^2 ~ EI / (rho A L^4) */
    lref = 1.0 / (sp.mass[1] * m->L * m->L * m->L);
    nel = sp.elements > 0 ? sp.elements : TR_MODES_ELEMENTS;
    rows = (double *)malloc(((size_t)m->nseg * TR_SR_NCOL + m->nseg + 1 + sp.npm) * sizeof(double));
    if (!rows) return TR_ENOMEM;
    gb = rows + (size_t)m->nseg * TR_SR_NCOL;
    at_solution(m, d, x, steps);
    for (;;) {
        /* the grids: the coarsest fine enough for the elements' rotations */
        if (ws_alloc(m, d, &sp, nel, gb, &s) < 0) {
            st = TR_ENOMEM;
            goto done;
        }
        if (s.nv < sp.n) {
            tr_msgf(o->message, sizeof o->message, "n = %d modes: more than the grid has", sp.n);
            st = TR_EINVAL;
            goto done;
        }
        st = tr_record_from(m, s.w.rec, d->x, d->steps);
        if (st != TR_OK) {
            tr_msgf(o->message, sizeof o->message, "the solution could not be recorded (%s)",
                    tr_strerror(st));
            goto done;
        }
        nn = grid_nodes(&s, 0);
        if (tr_stab_level_setup(m, d, &s.w, nn) == 0) break;
        if (2 * nel > TR_MODES_MAX_ELEMENTS) {
            tr_msgf(o->message, sizeof o->message, "the backbone turns too much for %d elements",
                    nel);
            st = TR_EINVAL;
            goto done;
        }
        ws_free(&s);
        nel *= 2;
    }
    start_vectors(&s, (nn - 1) * 6);
    for (l = 0; l < s.nlev; l++) {
        const tr_model *me;
        int ntot = 0, j;
        if (l > 0) {
            /* idx holds grid l - 1's blocks */
            prolong(&s, l);
            nn = grid_nodes(&s, l);
        }
        for (j = 1; j < nn; j++) ntot++;
        me = element_model(m, &mm, rows, m->L / ntot);
        if (tr_stab_level_setup(me, d, &s.w, nn) < 0) {
            tr_msgf(o->message, sizeof o->message, "an element turns too much");
            st = TR_EINVAL;
            goto done;
        }
        tr_stab_assemble(me, &s.w, nn, 6);
        lumped_mass(&sp, &s, nn);
        lmax = largest_bound(&s.w.h);
        st = grid_eigen(d, &s, nn, lref, lmax, &nit, &nfac);
        if (st == TR_ESINGULAR)
            tr_msgf(o->message, sizeof o->message,
                    "the eigenvalues of grid %d (%d elements) could not be separated (no shift "
                    "below the lowest, or an eigenvalue missed)",
                    l, nn - 1);
        if (st != TR_OK) goto done;
        for (i = 0; i < sp.n; i++) s.lam[l * sp.n + i] = s.th[i] * m->EI / m->L;
        s.lmax = lmax * m->EI / m->L;
        if (l + 1 < s.nlev) grid_nodes(&s, l); /* idx: this grid's blocks, for prolong */
    }
    {
        const size_t n = (size_t)sp.n, ns = (size_t)s.nfine;
        double *q =
            (double *)malloc((4 * n + (size_t)s.nlev * n + 4 * ns + 6 * n * ns) * sizeof(double));
        if (!q) {
            st = TR_ENOMEM;
            goto done;
        }
        o->omega2 = q, o->error = q + n, o->modal_mass = q + 2 * n, o->levels = q + 4 * n;
        q += 4 * n + (size_t)s.nlev * n;
        o->s = q, o->pos0 = q + ns, o->dpos = q + 4 * ns, o->drot = q + 4 * ns + 3 * n * ns;
        o->n = sp.n, o->nlev = s.nlev;
    }
    for (i = 0; i < sp.n; i++) {
        extrapolate(&s, i, o->omega2 + i, o->error + i);
        for (l = 0; l < s.nlev; l++) o->levels[l * sp.n + i] = s.lam[l * sp.n + i];
    }
    o->ns = s.nfine;
    shapes(m, &s, o);
    tr_msgf(o->message, sizeof o->message, "%d modes on %d grids (%d to %d elements)", sp.n, s.nlev,
            nel, s.nfine - 1);
done:
    o->nit = nit, o->nfac = nfac;
    if (st == TR_EINTERRUPTED || st == TR_EBUDGET)
        tr_msgf(o->message, sizeof o->message, "stopped: %s", tr_strerror(st));
    ws_free(&s);
    free(rows);
    return st;
}

void tr_modes_out_free(tr_modes_out *o)
{
    free(o->omega2);
    memset(o, 0, sizeof *o);
}
