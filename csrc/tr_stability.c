/*
 * tr_stability.c -- is the solved equilibrium a strict local minimum of the total
 * potential energy?  The constrained Hessian of a discretised energy (design and
 * validation: bench/results/stability_design.md).
 *
 * The solution is recorded at the nodes of a grid (uniform plus every breakpoint); the
 * coordinates are each node's body-frame rotation perturbation (and, with Cosserat
 * elements, its position perturbation), the base clamped.  The element energies are
 * tr_element.c's; Kirchhoff elements serve Cosserat rods too (they keep a symmetry's zero
 * mode exact; shear and extension move the margin by ~EI/(GA L^2) of the load scale),
 * Cosserat elements only where the tendon constraints are dependent on the Kirchhoff
 * ones.  A displacement-controlled tendon
 * adds EA/l (g g^T) for its stretch (finite EA) or makes g^T x = 0 a constraint
 * (inextensible), g the gradient of its length.  Element Hessians come exact to
 * round-off from hyper-dual numbers (tr_hd.h); the Hessian is block tridiagonal plus
 * those bordered terms, so its inertia follows from a block LDL^T (a Sturm sequence)
 * and Haynsworth's inertia additivity, and the margin (the smallest eigenvalue in the
 * norm (1/L) int |dtheta|^2 + |dp|^2/L^2 ds, scaled by EI/L) from a bisection on the
 * inertia of H - lambda M.  The margin at half the elements gives the discretisation
 * error; a margin within it is "critical", one at round-off level "neutral".  The quick
 * test (tr_stability_quick) decides from the inertia at +-band on a coarse grid alone
 * where no eigenvalue lies near zero, and leaves the margin to the full test.
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

void tr_stab_free(struct tr_stab_ws *w)
{
    if (!w) return;
    tr_data_free(w->rec);
    free(w->s);
    free(w->kind); /* with node */
    free(w->R);    /* with every other array */
    free(w);
}

/* The grid: nuni uniform elements and every breakpoint, sorted, merged within 1e-12 L. */
static struct tr_stab_ws *stab_alloc(const tr_model *m, const tr_options *opt, int nuni,
                                     int cosserat)
{
    struct tr_stab_ws *w = (struct tr_stab_ws *)calloc(1, sizeof *w);
    const int cap = nuni + m->nseg + 2, nb = cosserat ? 6 : 3, nt = m->nt > 0 ? m->nt : 1;
    const size_t nblk = (size_t)cap * nb * nb, nv = (size_t)cap * nb;
    size_t len;
    double *q;
    int i, b, n = 0;
    char msg[TR_MSGLEN];
    tr_options o = *opt;
    if (!w) return NULL;
    w->nuni = nuni, w->nb = nb, w->cosserat = cosserat;
    w->s = (double *)malloc((size_t)cap * sizeof(double));
    w->kind = (int *)malloc(((size_t)cap * 2 + nt) * sizeof(int));
    len = 18 * (size_t)cap + nt + 2 * nv + 5 * nblk + 2 * nv + 2 * nv * nt + 2 * (size_t)nt +
          2 * (size_t)nt * nt + 10 * nv;
    w->R = (double *)calloc(len, sizeof(double));
    if (!w->s || !w->kind || !w->R) {
        tr_stab_free(w);
        return NULL;
    }
    w->node = w->kind + cap;
    w->col = w->node + cap;
    q = w->R + 9 * cap;
    w->p = q, q += 3 * cap;
    w->F = q, q += 3 * cap;
    w->vhat = q, q += 3 * cap;
    w->tau = q, q += nt;
    w->g = q, q += nv;
    w->dx = q, q += nv;
    w->h.D = q, q += nblk;
    w->h.E = q, q += nblk;
    w->h.Pv = q, q += nblk;
    w->h.U = q, q += nblk;
    w->h.S = q, q += nblk; /* (nt x nt <= the space of a block array) */
    w->h.Mw = q, q += nv;
    w->h.Pe = q, q += nv;
    w->h.B = q, q += nv * nt;
    w->h.X = q, q += nv * nt;
    w->h.cb = q, q += nt;
    w->h.Se = q, q += nt;
    w->h.Sv = q, q += (size_t)nt * nt;
    if ((size_t)nt * nt > nblk) {
        /* many tendons on a short grid: the Schur complement gets its own space */
        w->h.S = q;
    }
    q += (size_t)nt * nt;
    w->sw_buf = q; /* 10 nv */
    for (i = 0, b = 1; i <= nuni || b < m->nseg;) {
        const double su = i <= nuni ? m->L * i / nuni : INFINITY;
        const double sb = b < m->nseg ? m->bp[b] : INFINITY;
        if (sb < su - 1e-12 * m->L) {
            w->s[n] = sb, w->kind[n++] = 1, b++;
        } else if (fabs(sb - su) <= 1e-12 * m->L) {
            w->s[n] = sb, w->kind[n++] = 1, b++, i++;
        } else {
            w->s[n] = i == nuni ? m->L : su, w->kind[n++] = i % 2 == 0, i++;
        }
    }
    w->ngrid = n;
    o.tip_only = 0;
    w->rec = tr_data_alloc(m, &o, n, w->s, msg, sizeof msg);
    if (!w->rec) {
        tr_stab_free(w);
        return NULL;
    }
    return w;
}

/* ------------------------------------------------------------ assembly */
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
int tr_stab_level_setup(const tr_model *m, const tr_data *d, struct tr_stab_ws *w, int nn)
{
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
        const int off = k > 0 ? nb : 0, ne = off + nb;
        tr_hd xa[TR_ELEM_NB], xb[TR_ELEM_NB];
        tr_elem e;
        int p, q;
        element(m, w, k, &e);
        for (p = 0; p < ne; p++)
            for (q = p; q < ne; q++) {
                tr_hd E;
                int ip, iq, bp_, bq_;
                for (c = 0; c < nb; c++) xa[c] = xb[c] = hd_c(0.0);
                if (p < off)
                    xa[p].a = 1.0;
                else
                    xb[p - off].a = 1.0;
                if (q < off)
                    xa[q].b += 1.0;
                else
                    xb[q - off].b += 1.0;
                E = tr_elem_energy(&e, xa, xb, -1);
                /* scatter: coordinate p of node a (p < off, block k - 1) or b (block k) */
                bp_ = p < off ? k - 1 : k, ip = p < off ? p : p - off;
                bq_ = q < off ? k - 1 : k, iq = q < off ? q : q - off;
                if (p == q) w->g[bp_ * nb + ip] += sc * E.a;
                if (bp_ == bq_) {
                    h->D[bp_ * nb2 + ip * nb + iq] += sc * E.c;
                    if (ip != iq) h->D[bp_ * nb2 + iq * nb + ip] += sc * E.c;
                } else {
                    h->E[bp_ * nb2 + ip * nb + iq] += sc * E.c;
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
            for (p = 0; p < ne; p++) {
                const int bp_ = p < off ? k - 1 : k, ip = p < off ? p : p - off;
                for (c = 0; c < nb; c++) xa[c] = xb[c] = hd_c(0.0);
                if (p < off)
                    xa[p].a = 1.0;
                else
                    xb[p - off].a = 1.0;
                h->B[(bp_ * nb + ip) * nbord + w->col[i]] += tr_elem_energy(&e, xa, xb, i).a;
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

/* ------------------------------------------------------------ the verdict */
double tr_stiffness_scale(const tr_model *m, const tr_data *d)
{
    double t = tr_load_scale(m);
    int i;
    for (i = 0; i < m->nt; i++) {
        const tr_tendon *tn = m->tendon + i;
        const double r = fmax(fabs(tn->b), fabs(tn->b + tn->a * tn->t));
        t += fabs(d->tau[i]) * r * m->L / m->EI;
    }
    return t;
}

/* The margin of one level (the grid nodes of kind >= min_kind) and the count of negative
 * modes; refine: first move to the discrete equilibrium.  *coarse: 1 too few elements, 2
 * the bordered constraints are dependent on these elements (no count). */
static double level_margin(const tr_model *m, const tr_data *d, struct tr_stab_ws *w, int min_kind,
                           int refine, int *index, int *coarse)
{
    const int nb = w->nb;
    int nn = 0, j, sing, neg;
    *coarse = 0;
    for (j = 0; j < w->ngrid; j++)
        if (w->kind[j] >= min_kind) w->node[nn++] = j;
    if (tr_stab_level_setup(m, d, w, nn) < 0) {
        *coarse = 1;
        return NAN;
    }
    tr_stab_assemble(m, w, nn, nb);
    if (refine) tr_stab_discrete_equilibrium(m, w, nn, nb);
    neg = tr_btd_count(&w->h, 0.0, &sing);
    if (sing) neg = tr_btd_count(&w->h, -1e-9, &sing);
    if (sing) {
        *coarse = 2;
        return NAN;
    }
    if (index) *index = neg;
    return tr_btd_smallest(&w->h, neg > 0);
}

/* A world-fixed point moment: not conservative for spatial perturbations (reason set). */
static int not_conservative(const tr_model *m, tr_data *d)
{
    int b;
    if (m->nfric > 0) {
        snprintf(d->stab_reason, sizeof d->stab_reason,
                 "not tested: friction in the tendon channels is not conservative (no energy "
                 "whose minimum decides stability)");
        return 1;
    }
    for (b = 1; b <= m->nseg; b++)
        if (m->bpM[3 * b] != 0.0 || m->bpM[3 * b + 1] != 0.0 || m->bpM[3 * b + 2] != 0.0) {
            snprintf(d->stab_reason, sizeof d->stab_reason,
                     "not tested: a point moment fixed in the world (at s = %g m) is not "
                     "conservative for spatial perturbations",
                     m->bp[b]);
            return 1;
        }
    return 0;
}

/* The workspace *wp for nuni uniform elements (reallocated when it has another count). */
struct tr_stab_ws *tr_stab_workspace(const tr_model *m, tr_data *d, struct tr_stab_ws **wp,
                                     int nuni, int cosserat)
{
    if (!*wp || (*wp)->nuni != nuni || (*wp)->cosserat != cosserat) {
        tr_stab_free(*wp);
        *wp = stab_alloc(m, &d->opt, nuni, cosserat);
    }
    return *wp;
}

static void verdict_reset(tr_data *d)
{
    d->stable = -1;
    d->stability = NAN;
    d->stab_index = -1;
    d->stab_gap = 0.0;
    d->stab_reason[0] = '\0';
}

static void slack_side_note(const tr_model *m, tr_data *d)
{
    int i;
    for (i = 0; i < m->nt; i++)
        if (m->tendon[i].control == TR_DISPLACEMENT && d->tau[i] == 0.0 && d->beta[i] == 0.0) {
            const size_t len = strlen(d->stab_reason);
            snprintf(d->stab_reason + len, sizeof d->stab_reason - len,
                     "; tendon %d is at its taut/slack switch: the slack side is tested", i);
        }
}

/* The full test: the model's own elements, refined near zero (sets the margin). */
/* near_zero: an eigenvalue is known to lie near zero (the quick test could not decide):
 * straight to the discrete equilibrium. */
static void verdict_full(const tr_model *m, tr_data *d, int near_zero)
{
    /* Kirchhoff elements, on a Cosserat rod too (they keep a symmetry's zero mode exact,
     * which the Cosserat elements resolve only to their discretisation error; shear and
     * extension move the margin by ~(1 + stiffness scale) EI/(GA L^2)), unless the
     * bordered constraints are dependent on them (opposing inextensible tendons held by
     * the backbone's extension): then the Cosserat elements */
    int cosserat = 0, nuni = d->stab ? d->stab->nuni : TR_STAB_ELEMENTS, coarse, st;
    int refine = near_zero;
    double mf = NAN, mc = NAN, err, reduction = 0.0;
    struct tr_stab_ws *w;
    for (;;) {
        w = tr_stab_workspace(m, d, &d->stab, nuni, cosserat);
        if (!w) {
            snprintf(d->stab_reason, sizeof d->stab_reason, "not tested: out of memory");
            return;
        }
        st = tr_record_from(m, w->rec, d->x, d->steps);
        if (st != TR_OK) {
            snprintf(d->stab_reason, sizeof d->stab_reason,
                     "not tested: the solution could not be recorded (%s)", tr_strerror(st));
            return;
        }
        mf = level_margin(m, d, w, 0, refine, &d->stab_index, &coarse);
        if (!coarse && !refine && fabs(mf) < TR_STAB_CHECK * (1.0 + tr_stiffness_scale(m, d))) {
            /* close to zero: at the discrete equilibrium, and against half the elements */
            refine = 1;
            mf = level_margin(m, d, w, 0, 1, &d->stab_index, &coarse);
        }
        mc = mf;
        /* the error estimate, unless the margin is at round-off (neutral) */
        if (!coarse && refine && !(fabs(mf) <= TR_STAB_NEUTRAL))
            mc = level_margin(m, d, w, 1, 1, NULL, &coarse);
        if (!coarse) break;
        if (coarse == 2) {
            if (cosserat || m->kirchhoff) {
                snprintf(d->stab_reason, sizeof d->stab_reason,
                         "not tested: the tendon constraints are dependent");
                return;
            }
            cosserat = 1, refine = 0;
            continue;
        }
        if (2 * nuni > TR_STAB_MAX_ELEMENTS) {
            snprintf(d->stab_reason, sizeof d->stab_reason,
                     "not tested: the backbone turns too much for %d elements", nuni);
            return;
        }
        nuni *= 2;
    }
    /* the discretisation error from half the elements (second order: the finer margin is
     * off by about a third of the change) */
    if (!m->kirchhoff && !cosserat)
        reduction =
            (1.0 + tr_stiffness_scale(m, d)) * m->EI * (1.0 / m->GA + 1.0 / m->EA) / (m->L * m->L);
    err = fabs(mf - mc) / 3.0 + reduction;
    d->stability = mf;
    if (fabs(mf) <= TR_STAB_NEUTRAL) {
        d->stable = 1;
        snprintf(d->stab_reason, sizeof d->stab_reason,
                 "neutrally stable: a direction of zero stiffness (margin %.2g EI/L), such as "
                 "a symmetry of the scene",
                 mf);
    } else if (fabs(mf) <= 2.0 * err) {
        snprintf(d->stab_reason, sizeof d->stab_reason,
                 "critical within the accuracy of the test: margin %.3g EI/L, discretisation "
                 "error about %.2g",
                 mf, err);
    } else {
        d->stable = mf > 0.0;
        d->stab_gap = fabs(mf) - 2.0 * err;
        snprintf(d->stab_reason, sizeof d->stab_reason, "%s: margin %.4g EI/L (%d negative %s)",
                 mf > 0.0 ? "stable" : "unstable", mf, d->stab_index,
                 d->stab_index == 1 ? "mode" : "modes");
    }
}

/* One eigenvalue in the quick test's band: a symmetry's zero mode?  At the discrete
 * equilibrium of the quick grid (where a symmetry's zero mode is exact to round-off) it
 * is neutral when that one eigenvalue lies within TR_STAB_NEUTRAL of zero and no other
 * within the band: stable when none lies below, the margin left to the full test.
 * Returns 1 when decided. */
static int quick_neutral(const tr_model *m, tr_data *d, struct tr_stab_ws *w, int nn, double band)
{
    int lo, hi, a, b, sing;
    tr_stab_discrete_equilibrium(m, w, nn, 3);
    lo = tr_btd_count(&w->h, -band, &sing);
    if (sing) return 0;
    hi = tr_btd_count(&w->h, band, &sing);
    if (sing || hi - lo != 1) return 0;
    a = tr_btd_count(&w->h, -TR_STAB_NEUTRAL, &sing);
    if (sing || a != lo) return 0;
    b = tr_btd_count(&w->h, TR_STAB_NEUTRAL, &sing);
    if (sing || b != hi) return 0;
    d->stable = lo == 0;
    d->stab_index = lo;
    d->stab_gap = 0.0; /* a zero mode: a kept verdict would not see it move */
    snprintf(d->stab_reason, sizeof d->stab_reason,
             "%s: a direction of zero stiffness (a symmetry of the scene), %d negative %s, no "
             "other eigenvalue within %.2g EI/L of zero",
             lo ? "unstable" : "neutrally stable", lo, lo == 1 ? "mode" : "modes", band);
    return 1;
}

/* The quick test: Kirchhoff elements on a coarse grid (TR_STAB_QUICK elements, doubled
 * while an element turns too much), no refinement; decides only when no eigenvalue lies
 * within +-TR_STAB_QUICK_BAND (1 + stiffness scale), where neither the model reduction
 * (shear and extension, O((d/L)^2)) nor the coarse grid's error can move one across
 * zero.  Returns 1 when decided (the margin stays NaN: the full test gives it on
 * request). */
static int verdict_quick(const tr_model *m, tr_data *d)
{
    const double band = TR_STAB_QUICK_BAND * (1.0 + tr_stiffness_scale(m, d));
    double gap;
    int nuni = TR_STAB_QUICK, nn, j, n0, nlo, nhi, sing;
    struct tr_stab_ws *w;
    for (;;) {
        w = tr_stab_workspace(m, d, &d->stab_quick, nuni, 0);
        if (!w || tr_record_from(m, w->rec, d->x, d->steps) != TR_OK) return 0;
        for (nn = j = 0; j < w->ngrid; j++) w->node[nn++] = j;
        if (tr_stab_level_setup(m, d, w, nn) == 0) break;
        if (2 * nuni > TR_STAB_MAX_ELEMENTS) return 0;
        nuni *= 2;
    }
    tr_stab_assemble(m, w, nn, 3);
    nlo = tr_btd_count(&w->h, -band, &sing);
    if (sing) return 0;
    nhi = tr_btd_count(&w->h, band, &sing);
    if (sing || nlo < 0) return 0;
    if (nhi - nlo == 1 && quick_neutral(m, d, w, nn, band)) return 1;
    if (nlo != nhi) return 0;
    n0 = nlo;
    /* how far from zero the nearest eigenvalue lies, in doublings of the band (a verdict
     * kept by warm solves lasts as long as their change stays small against it) */
    for (gap = band; gap < TR_STAB_QUICK_GAP * band; gap *= 2.0) {
        nlo = tr_btd_count(&w->h, -2.0 * gap, &sing);
        if (sing || nlo != n0) break;
        nhi = tr_btd_count(&w->h, 2.0 * gap, &sing);
        if (sing || nhi != n0) break;
    }
    d->stable = n0 == 0;
    d->stab_index = n0;
    d->stab_gap = gap;
    snprintf(d->stab_reason, sizeof d->stab_reason,
             "%s: %d negative %s, no eigenvalue within %.2g EI/L of zero",
             n0 ? "unstable" : "stable", n0, n0 == 1 ? "mode" : "modes", gap);
    return 1;
}

/* Unstable with tendons at their switch: the sides they resist tested too (tr_switch.c);
 * otherwise the note that the slack side was tested. */
static void switch_or_note(const tr_model *m, tr_data *d)
{
    if (d->stable == 0 && tr_switch_count(m, d) > 0)
        tr_switch_verdict(m, d);
    else
        slack_side_note(m, d);
}

void tr_stability(const tr_model *m, tr_data *d)
{
    verdict_reset(d);
    if (not_conservative(m, d)) return;
    tr_set_tensions(m, d, d->x);
    verdict_full(m, d, 0);
    switch_or_note(m, d);
}

void tr_stability_quick(const tr_model *m, tr_data *d)
{
    verdict_reset(d);
    if (not_conservative(m, d)) return;
    tr_set_tensions(m, d, d->x);
    if (!verdict_quick(m, d)) verdict_full(m, d, 1);
    switch_or_note(m, d);
}

int tr_stability_of(const tr_model *m, tr_data *d, const double *x, int steps, int quick)
{
    int i;
    if (d->model != m || steps < 1 || steps > TR_MAX_STEPS) {
        tr_set_message(d,
                       "tr_stability_of: a workspace of another model, or steps = %d out of "
                       "range",
                       steps);
        return TR_EINVAL;
    }
    tr_solve_reset(m, d, steps);
    memcpy(d->x, x, (size_t)d->k * sizeof(double));
    for (i = 0; i < d->k; i++)
        if (!isfinite(x[i])) {
            snprintf(d->stab_reason, sizeof d->stab_reason, "not tested: no solution");
            return TR_OK;
        }
    if (quick)
        tr_stability_quick(m, d);
    else
        tr_stability(m, d);
    return TR_OK;
}
