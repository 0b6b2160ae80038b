/*
 * tr_stab_energy.c -- the discretised energy of the stability test (tr_stab.h): the
 * elements of a grid level from the recorded state, the Hessian (block tridiagonal plus
 * the tendons' bordered terms, element Hessians exact in hyper-dual arithmetic), the
 * Newton steps to the discrete equilibrium, and the load-induced stiffness scale.  The
 * verdicts built on it are tr_stability.c's (the slack side) and tr_switch.c's (tendons
 * at their taut/slack switch); the grid's workspace is allocated in tr_data.c.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tendonrod.h"
#include "tr_element.h"
#include "tr_hd.h"
#include "tr_internal.h"
#include "tr_stab.h"
#include "tru_math.h"

/* The segment [bp[k], bp[k+1]) holding arc length s (the last one for s >= L). */
static int segment_at(const tr_model *m, double s)
{
    int k = 0;
    while (k + 1 < m->nseg && m->bp[k + 1] <= s) k++;
    return k;
}

/* Element k of the level (nodes w->node[k], w->node[k + 1]) at the configuration. */
static void element(const tr_model *m, const struct tr_stab_ws *w, int k, tr_elem *e)
{
    const int a = w->node[k], b = w->node[k + 1];
    int c;
    e->m = m, e->cosserat = w->cosserat, e->sa = w->s[a], e->sb = w->s[b];
    e->h = e->sb - e->sa, e->Ra = w->R + 9 * a, e->Rb = w->R + 9 * b, e->pa = w->p + 3 * a;
    e->pb = w->p + 3 * b, e->tau = w->tau;
    e->seg = segment_at(m, 0.5 * (e->sa + e->sb));
    e->sr = m->general ? m->seg_rod + (size_t)TR_SR_NCOL * e->seg : m->rod_k;
    for (c = 0; c < 3; c++) e->F[c] = w->F[3 * k + c], e->vhat[c] = w->vhat[3 * k + c];
}

/* The level's elements from the recorded state: the dead force beyond each (point forces
 * at later nodes, the distributed force with their trapezoid weights), the free strain of
 * each Cosserat element; the configuration and tensions reset to the recorded ones.
 * Returns 0, or -1 when an element turns by more than TR_STAB_MAX_ROT. */
int tr_stab_level_setup(const tr_model *m_, const tr_data *d, struct tr_stab_ws *w, int nn)
{
    const tr_model *m = TR_IN(m_, d);
    double Fb[3] = {0, 0, 0};
    int k, c, j;
    memcpy(w->R, w->rec->rot, (size_t)9 * w->ngrid * sizeof(double));
    memcpy(w->p, w->rec->pos, (size_t)3 * w->ngrid * sizeof(double));
    if (m->nt > 0) memcpy(w->tau, d->tau, (size_t)m->nt * sizeof(double));
    for (k = nn - 2; k >= 0; k--) {
        const int a = w->node[k], b = w->node[k + 1];
        const double hb = w->s[b] - w->s[a];
        const double hn = k + 2 < nn ? w->s[w->node[k + 2]] - w->s[b] : 0.0;
        const double *Ra = w->R + 9 * a, *Rb = w->R + 9 * b;
        double Qtr = 0.0;
        tr_elem e;
        for (j = 1; j <= m->nseg; j++)
            if (m->bp[j] == w->s[b])
                for (c = 0; c < 3; c++) Fb[c] += d->lam_load * m->bpF[3 * j + c];
        for (c = 0; c < 3; c++) Fb[c] += d->lam_load * m->dist[c] * 0.5 * (hb + hn);
        if (m->has_pdist) {
            /* half of each adjacent element's partial force, from the segment it lies on */
            const double *fa = m->seg_pdist + 3 * segment_at(m, w->s[a] + 0.5 * hb);
            const double *fn = hn > 0.0 ? m->seg_pdist + 3 * segment_at(m, w->s[b] + 0.5 * hn) : fa;
            for (c = 0; c < 3; c++)
                Fb[c] += d->lam_load * 0.5 * (fa[c] * hb + (hn > 0.0 ? fn[c] * hn : 0.0));
        }
        for (c = 0; c < 3; c++) w->F[3 * k + c] = Fb[c], w->vhat[3 * k + c] = 0.0;
        for (c = 0; c < 9; c++) Qtr += Ra[c] * Rb[c]; /* trace of Ra^T Rb */
        if (!(acos(fmax(-1.0, fmin(1.0, 0.5 * (Qtr - 1.0)))) <= TR_STAB_MAX_ROT)) return -1;
        if (w->cosserat) {
            /* The chord of a curved element is shorter than its arc by ~ (h kappa)^2 / 24,
             * which the axial stiffness EA would turn into a large spurious force: the
             * element's free strain is set so that its internal force at the recorded
             * state is the solution's at the element's middle, n_b = K_se (v - vhat). */
            const double *fa = w->rec->force + 3 * a, *fb = w->rec->force + 3 * b;
            tr_hd xz[TR_ELEM_NB], v0[3];
            double nbody[3], nw[3], ks[3];
            element(m, w, k, &e);
            ks[0] = ks[1] = e.sr[TR_SR_GA], ks[2] = e.sr[TR_SR_EA];
            for (c = 0; c < TR_ELEM_NB; c++) xz[c] = hd_c(0.0);
            tr_elem_strain(&e, xz, xz, v0);
            for (c = 0; c < 3; c++) nw[c] = 0.5 * (fa[c] + fb[c]);
            tr_elem_midframe_t(&e, nw, nbody);
            for (c = 0; c < 3; c++) w->vhat[3 * k + c] = v0[c].v - nbody[c] / ks[c];
        }
    }
    return 0;
}

/* The Hessian (scaled by L/EI), the gradient, the mass and the bordered columns of the
 * level at the configuration into w->h, w->g. */
void tr_stab_assemble(const tr_model *m, struct tr_stab_ws *w, int nn, int nb)
{
    const double sc = m->L / m->EI;
    const int nblk = nn - 1, n = nblk * nb, nb2 = nb * nb;
    tr_btd *h = &w->h;
    int nbord = 0, k, i, j, c;
    for (i = 0; i < nblk * nb2; i++) h->D[i] = h->E[i] = 0.0;
    for (i = 0; i < n; i++) w->g[i] = 0.0;
    /* the bordered columns: taut displacement-controlled tendons, with the compliance of
     * their stretch scaled like the Hessian, EI l / (L EA) (0: inextensible) */
    for (i = 0; i < m->nt; i++) {
        const tr_tendon *t = m->tendon + i;
        w->col[i] = -1;
        if (t->control != TR_DISPLACEMENT ||
            !(w->tau[i] > 0.0 || (i < 64 && (w->sw_mask >> i & 1ULL))))
            continue;
        w->col[i] = nbord;
        h->cb[nbord++] = isfinite(t->EA) ? m->EI * t->rest / (m->L * t->EA) : 0.0;
    }
    for (i = 0; i < n * (nbord > 0 ? nbord : 1); i++) h->B[i] = 0.0;
    h->nblk = nblk, h->nb = nb, h->nbord = nbord;
    /* the norm (1/L) int |dtheta|^2 ds: trapezoid weights / L on the rotations, none on
     * the positions of a Cosserat rod (so the margin means the same on both models) */
    for (j = 1; j < nn; j++) {
        const double hl = w->s[w->node[j]] - w->s[w->node[j - 1]];
        const double hr = j + 1 < nn ? w->s[w->node[j + 1]] - w->s[w->node[j]] : 0.0;
        for (c = 0; c < nb; c++) h->Mw[(j - 1) * nb + c] = c < 3 ? 0.5 * (hl + hr) / m->L : 0.0;
    }
    for (k = 0; k < nn - 1; k++) {
        const int off = k > 0 ? nb : 0;
        double g[2 * TR_ELEM_NB], He[4 * TR_ELEM_NB * TR_ELEM_NB], gc[6 * TR_ELEM_CHORDS];
        const int n2 = 2 * nb, chords = nb == 3 && nbord > 0 && m->nt <= TR_ELEM_CHORDS;
        tr_elem e;
        int p, q;
        element(m, w, k, &e);
        /* coordinates p < nb are node a's (block k - 1; none on the clamped first node),
         * the others node b's (block k); a Kirchhoff element's chord gradients come from
         * its Hessian's passes */
        if (chords)
            tr_elem_hessian_chords(&e, off == 0, g, He, gc);
        else
            tr_elem_hessian(&e, nb, off == 0, g, He);
        for (p = nb - off; p < n2; p++) {
            const int bp_ = p < nb ? k - 1 : k, ip = p < nb ? p : p - nb;
            w->g[bp_ * nb + ip] += sc * g[p];
            for (q = nb - off; q < n2; q++) {
                const int bq_ = q < nb ? k - 1 : k, iq = q < nb ? q : q - nb;
                if (bp_ == bq_)
                    h->D[bp_ * nb2 + ip * nb + iq] += sc * He[p * n2 + q];
                else if (bp_ < bq_)
                    h->E[bp_ * nb2 + ip * nb + iq] += sc * He[p * n2 + q];
            }
        }
        if (nb == 6) {
            /* Cosserat: the dead loads are linear in the positions (no Hessian) but part of
             * the gradient: the force at node b, F_beyond(k) - F_beyond(k + 1) */
            for (c = 0; c < 3; c++)
                w->g[k * nb + 3 + c] -=
                    sc * (w->F[3 * k + c] - (k + 2 < nn ? w->F[3 * (k + 1) + c] : 0.0));
        }
        for (i = 0; i < m->nt; i++) {
            if (w->col[i] < 0 || !(e.sb <= m->tendon[i].t * (1.0 + 1e-12))) continue;
            if (chords)
                for (p = 0; p < n2; p++) g[p] = gc[6 * i + p];
            else
                tr_elem_chord_gradient(&e, nb, off == 0, i, g);
            for (p = nb - off; p < n2; p++) {
                const int bp_ = p < nb ? k - 1 : k, ip = p < nb ? p : p - nb;
                h->B[(bp_ * nb + ip) * nbord + w->col[i]] += g[p];
            }
        }
    }
}

/* R exp(w^) for a rotation vector w (Rodrigues), in place. */
static void rotate(double *R, const double *w)
{
    const double th = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    const double A = th < 1e-8 ? 1.0 - th * th / 6.0 : sin(th) / th;
    const double B = th < 1e-8 ? 0.5 - th * th / 24.0 : (1.0 - cos(th)) / (th * th);
    double E[9], Rn[9];
    int i, j, k;
    E[0] = 1.0 - B * (w[1] * w[1] + w[2] * w[2]), E[4] = 1.0 - B * (w[0] * w[0] + w[2] * w[2]);
    E[8] = 1.0 - B * (w[0] * w[0] + w[1] * w[1]);
    E[1] = -A * w[2] + B * w[0] * w[1], E[3] = A * w[2] + B * w[0] * w[1];
    E[2] = A * w[1] + B * w[0] * w[2], E[6] = -A * w[1] + B * w[0] * w[2];
    E[5] = -A * w[0] + B * w[1] * w[2], E[7] = A * w[0] + B * w[1] * w[2];
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++) {
            double acc = 0.0;
            for (k = 0; k < 3; k++) acc += R[3 * i + k] * E[3 * k + j];
            Rn[3 * i + j] = acc;
        }
    memcpy(R, Rn, sizeof Rn);
}

/* Newton steps on the discretised energy from the recorded state: the state that the
 * continuum solution samples is an equilibrium of the discretisation only to O(h^2),
 * and a Hessian there turns an exact zero mode (a symmetry) into an O(h^2) one.  The
 * bordered tendons keep their discrete length (or stretch law), their tensions the
 * multipliers.  Stops quietly where a pivot is singular (the last assembly stands). */
void tr_stab_discrete_equilibrium(const tr_model *m, struct tr_stab_ws *w, int nn, int nb)
{
    const double sc = m->L / m->EI;
    tr_btd *h = &w->h;
    int it, i, r, c, q, sing;
    for (it = 0; it < TR_STAB_NEWTON; it++) {
        const int n = (nn - 1) * nb, nbord = h->nbord;
        double mu[64], Sm[64 * 64];
        /* a symmetry's zero mode makes H singular at the equilibrium: a slight shift
         * (1e-8 EI/L on the rotations) keeps the step defined, and damps only along it */
        tr_btd_count(h, 0.0, &sing);
        if (sing) tr_btd_count(h, -1e-8, &sing);
        if (sing) return;
        for (i = 0; i < n; i++) w->dx[i] = w->g[i];
        tr_btd_solve(h, w->dx, 1); /* y = H^-1 g */
        if (nbord > 0 && nbord <= 64) {
            /* S mu = B^T y, S = -C - B^T X (X = H^-1 B from the count) */
            for (r = 0; r < nbord; r++) {
                double acc = 0.0;
                for (q = 0; q < n; q++) acc += h->B[q * nbord + r] * w->dx[q];
                mu[r] = acc;
                for (c = 0; c < nbord; c++) {
                    double s2 = 0.0;
                    for (q = 0; q < n; q++) s2 += h->B[q * nbord + r] * h->X[q * nbord + c];
                    Sm[r * nbord + c] = -s2 - (r == c ? h->cb[r] : 0.0);
                }
            }
            if (tru_solve_dense(nbord, Sm, mu) != 0) return;
            for (q = 0; q < n; q++)
                for (c = 0; c < nbord; c++) w->dx[q] += h->X[q * nbord + c] * mu[c];
            for (i = 0; i < m->nt; i++)
                if (w->col[i] >= 0) w->tau[i] += mu[w->col[i]] / sc;
        }
        /* x -= dx: node j (1..nn-1) is block j - 1 */
        for (i = 1; i < nn; i++) {
            const int g = w->node[i];
            double dw[3];
            for (c = 0; c < 3; c++) dw[c] = -w->dx[(i - 1) * nb + c];
            rotate(w->R + 9 * g, dw);
            if (nb == 6)
                for (c = 0; c < 3; c++) w->p[3 * g + c] -= w->dx[(i - 1) * nb + 3 + c];
        }
        tr_stab_assemble(m, w, nn, nb);
    }
}

/* ------------------------------------------------------------ the load-induced stiffness */
double tr_stiffness_scale(const tr_model *m_, const tr_data *d)
{
    const tr_model *m = TR_IN(m_, d);
    double t = tr_load_scale(m);
    int i;
    for (i = 0; i < m->nt; i++) {
        const tr_tendon *tn = m->tendon + i;
        const double r = fmax(fabs(tn->b), fabs(tn->b + tn->a * tn->t));
        t += fabs(d->tau[i]) * r * m->L / m->EI;
    }
    return t;
}
