/*
 * tr_element.c -- one element of the discretised rod (tr_element.h): bending and torsion
 * from the log of the relative rotation of its nodes, less the precurvature's, with its
 * segment's rigidities; on a Kirchhoff element the position
 * follows the midpoint direction (dead loads act through the force beyond the element),
 * on a Cosserat one shear and extension from the chord in the midpoint frame; each taut
 * tendon adds its tension times the length of its chord between the eyelets (on its route:
 * linear, helical or piecewise).  Exact to
 * round-off in hyper-dual arithmetic, so that its Hessian is too.
 */
#include <math.h>

#include "tr_element.h"
#include "tru_math.h"

/* R (I + e^ + e^2/2): a rotation perturbed by the body-frame rotation vector e whose
 * value part is zero (exact in hyper-dual arithmetic: e^3 vanishes).  With
 * (e^2)_ij = e_i e_j - delta_ij |e|^2, and R constant, no product of two hyper-duals
 * but the six e_i e_j is needed. */
static void perturbed(tr_hd *out, const double *R, const tr_hd *e)
{
    tr_hd P[9], ee[6];
    int i, j;
    ee[0] = hd_mul(e[0], e[0]), ee[1] = hd_mul(e[1], e[1]), ee[2] = hd_mul(e[2], e[2]);
    ee[3] = hd_mul(e[0], e[1]), ee[4] = hd_mul(e[0], e[2]), ee[5] = hd_mul(e[1], e[2]);
    /* I + e^ + (e e^T - |e|^2 I) / 2 */
    P[0] = hd_add(hd_c(1.0), hd_scale(hd_add(ee[1], ee[2]), -0.5));
    P[4] = hd_add(hd_c(1.0), hd_scale(hd_add(ee[0], ee[2]), -0.5));
    P[8] = hd_add(hd_c(1.0), hd_scale(hd_add(ee[0], ee[1]), -0.5));
    P[1] = hd_sub(hd_scale(ee[3], 0.5), e[2]), P[3] = hd_add(hd_scale(ee[3], 0.5), e[2]);
    P[2] = hd_add(hd_scale(ee[4], 0.5), e[1]), P[6] = hd_sub(hd_scale(ee[4], 0.5), e[1]);
    P[5] = hd_sub(hd_scale(ee[5], 0.5), e[0]), P[7] = hd_add(hd_scale(ee[5], 0.5), e[0]);
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++)
            out[3 * i + j] =
                hd_lin3(P + j, R[3 * i], P + 3 + j, R[3 * i + 1], P + 6 + j, R[3 * i + 2]);
}

/* The rotation vector of Q (log map), smooth through Q = I. */
static void rot_log(tr_hd *w, const tr_hd *Q)
{
    tr_hd v[3], s2, f;
    const tr_hd cc = hd_scale(hd_sub(hd_add(hd_add(Q[0], Q[4]), Q[8]), hd_c(1.0)), 0.5);
    v[0] = hd_scale(hd_sub(Q[7], Q[5]), 0.5);
    v[1] = hd_scale(hd_sub(Q[2], Q[6]), 0.5);
    v[2] = hd_scale(hd_sub(Q[3], Q[1]), 0.5);
    s2 = hd_dot3(v, v);
    if (s2.v < 1e-6 && cc.v > 0.0) {
        /* theta / sin(theta) = asin(x) / x, x^2 = s2: its series (the x^10 term < 1e-16) */
        f = hd_add(hd_c(35.0 / 1152.0), hd_scale(s2, 63.0 / 2816.0));
        f = hd_add(hd_c(5.0 / 112.0), hd_mul(s2, f));
        f = hd_add(hd_c(3.0 / 40.0), hd_mul(s2, f));
        f = hd_add(hd_c(1.0 / 6.0), hd_mul(s2, f));
        f = hd_add(hd_c(1.0), hd_mul(s2, f));
    } else {
        const tr_hd sn = hd_sqrt(s2);
        f = hd_div(hd_atan2(sn, cc), sn);
    }
    w[0] = hd_mul(f, v[0]), w[1] = hd_mul(f, v[1]), w[2] = hd_mul(f, v[2]);
}

/* exp(W^) e3 for a rotation vector W, smooth through W = 0. */
static void exp_e3(tr_hd *out, const tr_hd *W)
{
    const tr_hd p2 = hd_dot3(W, W);
    tr_hd A, B;
    if (p2.v < 1e-4) {
        A = hd_add(
            hd_c(1.0),
            hd_mul(p2, hd_add(hd_c(-1.0 / 6.0),
                              hd_mul(p2, hd_add(hd_c(1.0 / 120.0), hd_scale(p2, -1.0 / 5040.0))))));
        B = hd_add(hd_c(0.5), hd_mul(p2, hd_add(hd_c(-1.0 / 24.0),
                                                hd_mul(p2, hd_add(hd_c(1.0 / 720.0),
                                                                  hd_scale(p2, -1.0 / 40320.0))))));
    } else {
        const tr_hd p = hd_sqrt(p2);
        const tr_hd sp = hd_fn(p, sin(p.v), cos(p.v), -sin(p.v));
        const tr_hd cp = hd_fn(p, cos(p.v), -sin(p.v), -cos(p.v));
        A = hd_div(sp, p);
        B = hd_div(hd_sub(hd_c(1.0), cp), p2);
    }
    out[0] = hd_add(hd_mul(A, W[1]), hd_mul(B, hd_mul(W[0], W[2])));
    out[1] = hd_add(hd_scale(hd_mul(A, W[0]), -1.0), hd_mul(B, hd_mul(W[1], W[2])));
    out[2] = hd_add(hd_c(1.0), hd_mul(B, hd_sub(hd_mul(W[2], W[2]), p2)));
}

/* Eyelet offset of tendon i at arc length s on the element's segment, body frame [m]
 * (its route: linear, helical or piecewise). */
static void eyelet(const tr_elem *e, int i, double s, double *r)
{
    double rp[3];
    tr_tendon_offset(e->m, i, e->seg, s, r, rp);
}

/* The kinematics of element e at the perturbations xa, xb of its nodes: the node
 * rotations, Ra^T, the relative rotation vector w, W = w / 2 and the midpoint
 * direction d = Ra exp(W^) e3 (world). */
typedef struct {
    tr_hd Ra[9], Rb[9], Ra_t[9], w[3], W[3], d[3];
} kin;

static void elem_kin(const tr_elem *e, const tr_hd *xa, const tr_hd *xb, kin *k)
{
    tr_hd Q[9], dm[3];
    int i, c;
    perturbed(k->Ra, e->Ra, xa);
    perturbed(k->Rb, e->Rb, xb);
    for (i = 0; i < 3; i++)
        for (c = 0; c < 3; c++) k->Ra_t[3 * i + c] = k->Ra[3 * c + i];
    hd_matmul3(Q, k->Ra_t, k->Rb);
    rot_log(k->w, Q);
    for (c = 0; c < 3; c++) k->W[c] = hd_scale(k->w[c], 0.5);
    exp_e3(dm, k->W);
    hd_matvec3(k->d, k->Ra, dm);
}

/* Rm^T x for the midpoint frame Rm = Ra exp(W^): exp(-W^) Ra^T x.  The columns of
 * exp(-W^): its image of e3 from exp_e3, of e1 and e2 by a cyclic relabelling of the
 * axes (a proper rotation of the coordinates). */
static void mid_t(const kin *k, const tr_hd *x, tr_hd *out)
{
    tr_hd y[3], Wn[3], Wp[3], col[3], e1[3], e2[3], E3[9];
    int c;
    hd_matvec3(y, k->Ra_t, x);
    for (c = 0; c < 3; c++) Wn[c] = hd_scale(k->W[c], -1.0);
    Wp[0] = Wn[1], Wp[1] = Wn[2], Wp[2] = Wn[0];
    exp_e3(col, Wp); /* exp(-W^) e1 in the relabelled axes (y, z, x) */
    e1[0] = col[2], e1[1] = col[0], e1[2] = col[1];
    Wp[0] = Wn[2], Wp[1] = Wn[0], Wp[2] = Wn[1];
    exp_e3(col, Wp); /* exp(-W^) e2 in the axes (z, x, y) */
    e2[0] = col[1], e2[1] = col[2], e2[2] = col[0];
    exp_e3(col, Wn);
    for (c = 0; c < 3; c++) E3[3 * c] = e1[c], E3[3 * c + 1] = e2[c], E3[3 * c + 2] = col[c];
    hd_matvec3(out, E3, y);
}

/* The centre line's chord of element e: p_b - p_a (Cosserat coordinates), or h d. */
static void centre_chord(const tr_elem *e, const kin *k, const tr_hd *xa, const tr_hd *xb,
                         tr_hd *chord)
{
    int c;
    for (c = 0; c < 3; c++)
        chord[c] = e->cosserat ? hd_sub(hd_add(hd_c(e->pb[c]), xb[3 + c]),
                                        hd_add(hd_c(e->pa[c]), xa[3 + c]))
                               : hd_scale(k->d[c], e->h);
}

/* Cosserat: the strain v = Rm^T (p_b - p_a) / h of element e. */
void tr_elem_strain(const tr_elem *e, const tr_hd *xa, const tr_hd *xb, tr_hd *v)
{
    kin k;
    tr_hd chord[3];
    int c;
    elem_kin(e, xa, xb, &k);
    centre_chord(e, &k, xa, xb, chord);
    mid_t(&k, chord, v);
    for (c = 0; c < 3; c++) v[c] = hd_scale(v[c], 1.0 / e->h);
}

/* Rm^T x at the recorded state (no perturbation), x world. */
void tr_elem_midframe_t(const tr_elem *e, const double *x, double *out)
{
    kin k;
    tr_hd xz[TR_ELEM_NB], xh[3], o[3];
    int c;
    for (c = 0; c < TR_ELEM_NB; c++) xz[c] = hd_c(0.0);
    elem_kin(e, xz, xz, &k);
    for (c = 0; c < 3; c++) xh[c] = hd_c(x[c]);
    mid_t(&k, xh, o);
    for (c = 0; c < 3; c++) out[c] = o[c].v;
}

/* Energy of element e as a function of the perturbations xa, xb (nb each) of its
 * nodes; only == -1: the whole energy, only >= 0: the length of tendon only's chord. */
tr_hd tr_elem_energy(const tr_elem *e, const tr_hd *xa, const tr_hd *xb, int only)
{
    const tr_model *m = e->m;
    const double K[3] = {e->sr[TR_SR_EI], e->sr[TR_SR_EI], e->sr[TR_SR_GJ]};
    tr_hd E = hd_c(0.0), chord[3];
    kin k;
    int i, c;
    elem_kin(e, xa, xb, &k);
    centre_chord(e, &k, xa, xb, chord);
    if (only < 0) {
        /* bending and torsion about the precurvature: the unstressed relative rotation of
         * the nodes is exp(h u*) */
        for (c = 0; c < 3; c++) {
            const tr_hd dw = hd_sub(k.w[c], hd_c(e->h * e->sr[TR_SR_U + c]));
            E = hd_add(E, hd_scale(hd_mul(dw, dw), 0.5 * K[c] / e->h));
        }
        if (e->cosserat) {
            const double ks[3] = {e->sr[TR_SR_GA], e->sr[TR_SR_GA], e->sr[TR_SR_EA]};
            tr_hd v[3];
            mid_t(&k, chord, v);
            for (c = 0; c < 3; c++) {
                const tr_hd dv = hd_sub(hd_scale(v[c], 1.0 / e->h), hd_c(e->vhat[c]));
                E = hd_add(E, hd_scale(hd_mul(dv, dv), 0.5 * e->h * ks[c]));
            }
        } else {
            /* dead loads through the element's direction: -h F . d */
            for (c = 0; c < 3; c++) E = hd_sub(E, hd_scale(k.d[c], e->h * e->F[c]));
        }
    }
    for (i = 0; i < m->nt; i++) {
        const tr_tendon *t = m->tendon + i;
        double ra[3], rb[3];
        tr_hd Rra[3], Rrb[3], ci[3], len;
        if (only >= 0 && i != only) continue;
        if (only < 0 && !(e->tau[i] > 0.0)) continue;
        if (!(e->sb <= t->t * (1.0 + 1e-12))) continue;
        eyelet(e, i, e->sa, ra);
        eyelet(e, i, e->sb, rb);
        hd_matvec3c(Rra, k.Ra, ra);
        hd_matvec3c(Rrb, k.Rb, rb);
        for (c = 0; c < 3; c++) ci[c] = hd_sub(hd_add(chord[c], Rrb[c]), Rra[c]);
        len = hd_sqrt(hd_dot3(ci, ci));
        if (only >= 0) return len;
        E = hd_add(E, hd_scale(len, e->tau[i]));
    }
    return only >= 0 ? hd_c(0.0) : E;
}

/* Variable v of the Hessian's passes: node a's rotation (0-2), node b's (3-5) and, on a
 * Cosserat element, the chord's change (6-8): the energy sees the positions only through
 * p_b - p_a, so that perturbing p_b alone gives the derivatives along it. */
static void seed(tr_hd *xa, tr_hd *xb, int v, int which)
{
    tr_hd *x = v < 3 ? xa + v : v < 6 ? xb + v - 3 : xb + v - 3;
    if (which == 0)
        x->a += 1.0;
    else
        x->b += 1.0;
}

/* coordinate p of the element (node a's nb, then node b's): its variable and sign */
static void coordinates(int nb, int *vr, double *sg)
{
    int p;
    for (p = 0; p < 2 * nb; p++) {
        const int node = p / nb, c = p % nb;
        vr[p] = c < 3 ? 3 * node + c : 6 + (c - 3);
        sg[p] = c >= 3 && node == 0 ? -1.0 : 1.0;
    }
}

/* A Kirchhoff element's energy apart from its dead loads -- bending, torsion and the
 * tendons' chords -- sees its nodes' rotations only through the relative rotation
 * Q = Ra^T Rb (a chord's length |h d + Rb r_b - Ra r_a| is that of
 * h exp(W^) e3 + Q r_b - r_a in node a's frame); with Q = Q0 exp(z^) it is G(z).  Returns
 * G and the midpoint direction in node a's frame, m = exp(W^) e3, at the perturbation z;
 * only as tr_elem_energy's. */
static tr_hd rel_energy(const tr_elem *e, const double *Q0, const tr_hd *z, int only, tr_hd *mdir,
                        tr_hd *lens)
{
    const tr_model *m = e->m;
    const double K[3] = {e->sr[TR_SR_EI], e->sr[TR_SR_EI], e->sr[TR_SR_GJ]};
    tr_hd Q[9], w[3], W[3], E = hd_c(0.0);
    int i, c;
    perturbed(Q, Q0, z);
    rot_log(w, Q);
    for (c = 0; c < 3; c++) W[c] = hd_scale(w[c], 0.5);
    exp_e3(mdir, W);
    if (only < 0)
        for (c = 0; c < 3; c++) {
            const tr_hd dw = hd_sub(w[c], hd_c(e->h * e->sr[TR_SR_U + c]));
            E = hd_add(E, hd_scale(hd_mul(dw, dw), 0.5 * K[c] / e->h));
        }
    for (i = 0; i < m->nt; i++) {
        const tr_tendon *t = m->tendon + i;
        double ra[3], rb[3];
        tr_hd Qrb[3], ci[3], len;
        if (lens) lens[i] = hd_c(0.0);
        if (only >= 0 && i != only) continue;
        if (only < 0 && !(e->tau[i] > 0.0) && !lens) continue;
        if (!(e->sb <= t->t * (1.0 + 1e-12))) continue;
        eyelet(e, i, e->sa, ra);
        eyelet(e, i, e->sb, rb);
        hd_matvec3c(Qrb, Q, rb);
        for (c = 0; c < 3; c++)
            ci[c] = hd_add(hd_scale(mdir[c], e->h), hd_sub(Qrb[c], hd_c(ra[c])));
        len = hd_sqrt(hd_dot3(ci, ci));
        if (only >= 0) return len;
        if (lens) lens[i] = len;
        if (e->tau[i] > 0.0) E = hd_add(E, hd_scale(len, e->tau[i]));
    }
    return only >= 0 ? hd_c(0.0) : E;
}

/* The Kirchhoff element's Hessian from six passes of rel_energy.  With the perturbations
 * xa, xb of the nodes, Q = exp(-xa^) Q0 exp(xb^) = Q0 exp(z^), z = A x + (a x b) / 2 + O(3)
 * (Baker-Campbell-Hausdorff), a = -Q0^T xa, b = xb, A = [-Q0^T, I]: the energy G(z) has
 * gradient A^T G' and Hessian A^T G'' A plus G' . (a x b) / 2 in the mixed block,
 * (Q0 G'^)/2.  The dead loads, -h F . Ra exp(xa^) m(z) = -h f . exp(xa^) m(z)
 * (f = Ra^T F), add f . m(z) like G, xa . (m(z) x f) to first order in z (the bilinear
 * xa^T f^ Jm A x) and the quadratic (f . xa)(m0 . xa) - (f . m0)|xa|^2 over 2. */
static double kirchhoff_hessian(const tr_elem *e, int clamped_a, double *g, double *H, double *gc)
{
    const int only = -1, nt = gc ? e->m->nt : 0;
    double gl[3 * TR_ELEM_CHORDS];
    tr_hd lens[TR_ELEM_CHORDS];
    double Q0[9], A[18], gz[3], Hz[9], m0[3], Jm[9], Hf[9], f[3], C[18], gG[3];
    double fh = 0.0, E0 = 0.0;
    int u, v, i, j, k, c;
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++) {
            double acc = 0.0;
            for (k = 0; k < 3; k++) acc += e->Ra[3 * k + i] * e->Rb[3 * k + j];
            Q0[3 * i + j] = acc;
        }
    for (i = 0; i < 3; i++) {
        f[i] = 0.0;
        if (only < 0)
            for (k = 0; k < 3; k++) f[i] += e->Ra[3 * k + i] * e->F[k];
        fh += f[i] * f[i];
    }
    /* G and m, their gradients (Jm[c][u] = dm_c / dz_u) and Hessians (f . m's in Hf) */
    for (u = 0; u < 3; u++)
        for (v = u; v < 3; v++) {
            tr_hd z[3], md[3], G;
            for (c = 0; c < 3; c++) z[c] = hd_c(0.0);
            z[u].a += 1.0;
            z[v].b += 1.0;
            G = rel_energy(e, Q0, z, only, md, gc ? lens : NULL);
            Hz[3 * u + v] = Hz[3 * v + u] = G.c;
            Hf[3 * u + v] = Hf[3 * v + u] = f[0] * md[0].c + f[1] * md[1].c + f[2] * md[2].c;
            if (u == v) {
                gz[u] = G.a, E0 = G.v;
                for (c = 0; c < 3; c++) Jm[3 * c + u] = md[c].a, m0[c] = md[c].v;
                for (i = 0; i < nt; i++) gl[3 * i + u] = lens[i].a;
            }
        }
    /* the dead load's share of z's energy: -h f . m(z) */
    for (u = 0; u < 3; u++) {
        gG[u] = gz[u];
        for (c = 0; c < 3; c++) gG[u] -= e->h * f[c] * Jm[3 * c + u];
        for (v = 0; v < 3; v++) Hz[3 * u + v] -= e->h * Hf[3 * u + v];
    }
    if (fh > 0.0) E0 -= e->h * (f[0] * m0[0] + f[1] * m0[1] + f[2] * m0[2]);
    /* A = [-Q0^T, I] (3 x 6) */
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++) A[6 * i + j] = -Q0[3 * j + i], A[6 * i + 3 + j] = i == j;
    for (i = 0; i < 6; i++) {
        g[i] = 0.0;
        for (k = 0; k < 3; k++) g[i] += A[6 * k + i] * gG[k];
        for (j = 0; j < 6; j++) {
            double acc = 0.0;
            for (k = 0; k < 3; k++)
                for (c = 0; c < 3; c++) acc += A[6 * k + i] * Hz[3 * k + c] * A[6 * c + j];
            H[6 * i + j] = acc;
        }
    }
    /* the mixed block's BCH term: (Q0 gG^)[m][j] / 2 for xa_m, xb_j */
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++) {
            const double gh[9] = {0, -gG[2], gG[1], gG[2], 0, -gG[0], -gG[1], gG[0], 0};
            double acc = 0.0;
            for (k = 0; k < 3; k++) acc += Q0[3 * i + k] * gh[3 * k + j];
            H[6 * i + 3 + j] += 0.5 * acc;
            H[6 * (3 + j) + i] += 0.5 * acc;
        }
    if (fh > 0.0) {
        /* exp(xa^)'s first order: -h xa . (m(z) x f): gradient -h m0 x f, and the bilinear
         * -h xa^T f^T Jm A x (C = h f^ Jm A, 3 x 6) */
        const double fhat[9] = {0, -f[2], f[1], f[2], 0, -f[0], -f[1], f[0], 0};
        g[0] -= e->h * (m0[1] * f[2] - m0[2] * f[1]);
        g[1] -= e->h * (m0[2] * f[0] - m0[0] * f[2]);
        g[2] -= e->h * (m0[0] * f[1] - m0[1] * f[0]);
        for (i = 0; i < 3; i++)
            for (j = 0; j < 6; j++) {
                double acc = 0.0;
                for (k = 0; k < 3; k++) {
                    double fj = 0.0;
                    for (c = 0; c < 3; c++) fj += Jm[3 * k + c] * A[6 * c + j];
                    acc += fhat[3 * i + k] * fj;
                }
                C[6 * i + j] = e->h * acc;
            }
        for (i = 0; i < 3; i++)
            for (j = 0; j < 6; j++) H[6 * i + j] += C[6 * i + j], H[6 * j + i] += C[6 * i + j];
        /* exp(xa^)'s second order */
        {
            const double fm = f[0] * m0[0] + f[1] * m0[1] + f[2] * m0[2];
            for (i = 0; i < 3; i++)
                for (j = 0; j < 3; j++)
                    H[6 * i + j] -=
                        e->h * (0.5 * (f[i] * m0[j] + m0[i] * f[j]) - (i == j ? fm : 0.0));
        }
    }
    /* the chords' gradients: A^T dlen/dz */
    for (i = 0; i < nt; i++)
        for (u = 0; u < 3; u++) {
            double acc = 0.0;
            for (k = 0; k < 3; k++) acc -= Q0[3 * u + k] * gl[3 * i + k];
            gc[6 * i + 3 + u] = gl[3 * i + u];
            gc[6 * i + u] = clamped_a ? 0.0 : acc;
        }
    if (clamped_a) /* node a's rows and columns left zero */
        for (i = 0; i < 6; i++) {
            if (i < 3) g[i] = 0.0;
            for (j = 0; j < 6; j++)
                if (i < 3 || j < 3) H[6 * i + j] = 0.0;
        }
    return E0;
}

double tr_elem_hessian(const tr_elem *e, int nb, int clamped_a, double *g, double *H)
{
    if (nb == 3 && !e->cosserat) return kirchhoff_hessian(e, clamped_a, g, H, NULL);
    const int n = 2 * nb, nv = nb == 6 ? 9 : 6;
    double Hv[81], gv[9], sg[2 * TR_ELEM_NB], E0 = 0.0;
    int vr[2 * TR_ELEM_NB], u, v, c, p, q;
    for (u = 0; u < nv * nv; u++) Hv[u] = 0.0;
    for (u = 0; u < nv; u++) gv[u] = 0.0;
    for (u = clamped_a ? 3 : 0; u < nv; u++)
        for (v = u; v < nv; v++) {
            tr_hd xa[TR_ELEM_NB], xb[TR_ELEM_NB], E;
            for (c = 0; c < TR_ELEM_NB; c++) xa[c] = xb[c] = hd_c(0.0);
            seed(xa, xb, u, 0);
            seed(xa, xb, v, 1);
            E = tr_elem_energy(e, xa, xb, -1);
            Hv[u * nv + v] = Hv[v * nv + u] = E.c;
            if (u == v) gv[u] = E.a, E0 = E.v;
        }
    coordinates(nb, vr, sg);
    for (p = 0; p < n; p++) g[p] = sg[p] * gv[vr[p]];
    for (p = 0; p < n; p++)
        for (q = 0; q < n; q++) H[p * n + q] = sg[p] * sg[q] * Hv[vr[p] * nv + vr[q]];
    return E0;
}

double tr_elem_hessian_chords(const tr_elem *e, int clamped_a, double *g, double *H, double *gc)
{
    return kirchhoff_hessian(e, clamped_a, g, H, gc);
}

void tr_elem_chord_gradient(const tr_elem *e, int nb, int clamped_a, int i, double *g)
{
    const int nv = nb == 6 ? 9 : 6;
    double gv[9], sg[2 * TR_ELEM_NB];
    int vr[2 * TR_ELEM_NB], u, c, p;
    if (nb == 3 && !e->cosserat) {
        /* the chord's length is a function of z alone (rel_energy): g = A^T dlen/dz */
        double Q0[9], gz[3];
        int k;
        for (u = 0; u < 3; u++)
            for (c = 0; c < 3; c++) {
                double acc = 0.0;
                for (k = 0; k < 3; k++) acc += e->Ra[3 * k + u] * e->Rb[3 * k + c];
                Q0[3 * u + c] = acc;
            }
        for (u = 0; u < 3; u++) {
            tr_hd z[3], md[3];
            for (c = 0; c < 3; c++) z[c] = hd_c(0.0);
            z[u].a += 1.0;
            gz[u] = rel_energy(e, Q0, z, i, md, NULL).a;
        }
        for (u = 0; u < 3; u++) {
            g[3 + u] = gz[u];
            g[u] = 0.0;
            if (!clamped_a)
                for (k = 0; k < 3; k++) g[u] -= Q0[3 * u + k] * gz[k];
        }
        return;
    }
    for (u = 0; u < nv; u++) {
        tr_hd xa[TR_ELEM_NB], xb[TR_ELEM_NB];
        gv[u] = 0.0;
        if (clamped_a && u < 3) continue;
        for (c = 0; c < TR_ELEM_NB; c++) xa[c] = xb[c] = hd_c(0.0);
        seed(xa, xb, u, 0);
        gv[u] = tr_elem_energy(e, xa, xb, i).a;
    }
    coordinates(nb, vr, sg);
    for (p = 0; p < 2 * nb; p++) g[p] = sg[p] * gv[vr[p]];
}
