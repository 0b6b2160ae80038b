/*
 * tr_guess.c -- where a solve starts: the cold guess (small-deflection linear model
 * and the shape pass), the node unknowns of multiple shooting, and the one map
 * between a physical guess and the scaled unknowns (both directions).
 */
#include <math.h>
#include <string.h>

#include "tendonrod.h"
#include "tr_internal.h"
#include "tru_math.h"

/* The force/moment unknowns of a base reaction F [N], M [N m] (world = base frame):
 * scaled, planar x, z force and y moment. */
static void base_unknowns(const tr_model *m, const double F[3], const double M[3], double *x)
{
    int c;
    if (m->planar) {
        x[0] = F[0] / m->F_s;
        x[1] = F[2] / m->F_s;
        x[2] = M[1] / m->M_s;
    } else {
        for (c = 0; c < 3; c++) {
            x[c] = F[c] / m->F_s;
            x[3 + c] = M[c] / m->M_s;
        }
    }
}

/* Shape pass of a cold start: integrate the robot under its (guessed) tensions with
 * the loads off, record the pose at every breakpoint, then
 *  - set the base-reaction moment unknowns to the moment of the loads about the
 *    base in that actuated shape (the straight-robot estimate misses e.g. a vertical
 *    load on a bent robot), and
 *  - with multiple shooting, set each node to the unloaded state plus the section
 *    load (force and moment of the distal loads about the node, in that shape):
 *    under tensile loads this keeps every segment near its linear regime.
 * Where the pass does not stay finite, the straight robot stands in. */
static void shape_guess(const tr_model *m, tr_data *d, double *x)
{
    const int ns = m->n_states, nf = tr_n_force(m);
    double *y = d->y, *pose = d->bp_pose;
    const double lam_load = d->lam_load;
    d->y_steps = -1; /* y becomes the shape pass's state */
    int b, c, ok = 1;
    /* unloaded base state: base reaction zero */
    for (c = 0; c < nf; c++) d->xt[c] = 0.0;
    for (c = nf; c < d->k; c++) d->xt[c] = x[c];
    d->rec = 0;
    d->lam_load = 0.0;
    tr_set_tensions(m, d, d->xt);
    tr_init_state(m, d, d->xt, y, ns);
    for (b = 0; b <= m->nseg; b++) {
        if (b > 0) {
            d->seg = b - 1;
            if (ok && tr_integrate(m, d, m->bp[b - 1], m->bp[b], tr_segment_steps(m, d, b - 1),
                                   y) != TR_OK)
                ok = 0;
            if (ok && b < m->nseg) tr_apply_jump(m, d, b, y);
        }
        if (ok) {
            double n_[3], mo[3];
            tr_state_world(m, y, pose + 12 * b, pose + 12 * b + 3, n_, mo);
            for (c = 0; c < 12 && ok; c++)
                if (!isfinite(pose[12 * b + c])) ok = 0;
        }
        if (!ok) {
            /* straight robot */
            memset(pose + 12 * b, 0, 12 * sizeof(double));
            pose[12 * b + 2] = m->bp[b];
            pose[12 * b + 3] = pose[12 * b + 7] = pose[12 * b + 11] = 1.0;
        }
        if (b > 0 && b < m->nseg && m->bp_node[b] > 0) {
            /* unloaded state, stored for the node (loads added below) */
            const int o = tr_node_off(m, m->bp_node[b]);
            for (c = 0; c < ns; c++)
                x[o + c] = ok ? y[c] : (c == (m->planar ? TR_YP_Z : TR_Y_P + 2) ? m->bp[b] : 0.0);
            if (!ok && !m->planar) x[o + TR_Y_R] = x[o + TR_Y_R + 4] = x[o + TR_Y_R + 8] = 1.0;
        }
    }
    d->lam_load = lam_load;
    /* loads about each section in that shape */
    for (b = 0; b < m->nseg; b++) {
        double F[3] = {0, 0, 0}, M[3] = {0, 0, 0}, arm[3], tmp[3];
        const double *pb = pose + 12 * b;
        int bb;
        if (b > 0 && (b >= m->nseg || m->bp_node[b] == 0)) continue;
        for (bb = b + 1; bb <= m->nseg; bb++) {
            const double *Fb = m->bpF + 3 * bb;
            for (c = 0; c < 3; c++) arm[c] = pose[12 * bb + c] - pb[c];
            tru_cross3(tmp, arm, Fb);
            for (c = 0; c < 3; c++) {
                F[c] += lam_load * Fb[c];
                M[c] += lam_load * (tmp[c] + m->bpM[3 * bb + c]);
            }
        }
        if (m->has_dist) {
            /* int_s^L (p - p_b) x f: trapezoid over the breakpoints */
            for (bb = b + 1; bb <= m->nseg; bb++) {
                const double h = m->bp[bb] - m->bp[bb - 1];
                double mid[3];
                for (c = 0; c < 3; c++)
                    mid[c] = 0.5 * (pose[12 * bb + c] + pose[12 * (bb - 1) + c]) - pb[c];
                tru_cross3(tmp, mid, m->dist);
                for (c = 0; c < 3; c++) M[c] += lam_load * h * tmp[c];
            }
            for (c = 0; c < 3; c++) F[c] += lam_load * (m->L - m->bp[b]) * m->dist[c];
        }
        if (m->has_pdist) {
            /* the same trapezoid, each segment with its own partial force */
            for (bb = b + 1; bb <= m->nseg; bb++) {
                const double h = m->bp[bb] - m->bp[bb - 1], *f = m->seg_pdist + 3 * (bb - 1);
                double mid[3];
                for (c = 0; c < 3; c++)
                    mid[c] = 0.5 * (pose[12 * bb + c] + pose[12 * (bb - 1) + c]) - pb[c];
                tru_cross3(tmp, mid, f);
                for (c = 0; c < 3; c++) {
                    M[c] += lam_load * h * tmp[c];
                    F[c] += lam_load * h * f[c];
                }
            }
        }
        if (b == 0) {
            /* base reaction (world = base frame) */
            base_unknowns(m, F, M, x);
        } else {
            const int o = tr_node_off(m, m->bp_node[b]);
            const double *R = pb + 3;
            double Fb[3], Mb[3];
            tru_mattvec3(Fb, R, F);
            tru_mattvec3(Mb, R, M);
            if (m->planar) {
                x[o + TR_YP_N1] += Fb[0];
                x[o + TR_YP_N3] += Fb[2];
                x[o + TR_YP_M] += Mb[1];
            } else {
                for (c = 0; c < 3; c++) {
                    x[o + TR_Y_N + c] += Fb[c];
                    x[o + TR_Y_M + c] += Mb[c];
                }
            }
            for (c = 0; c < ns; c++) x[o + c] /= tr_node_scale(m, c);
        }
    }
}

static void cold_guess(const tr_model *m, tr_data *d, double *x);

/* Cold start: the straight-robot base moment or the shape pass's, whichever has
 * the smaller residual (a load on a bent robot wants the shape; a strong tensile
 * load that straightens the robot wants the straight one); nodes from the shape. */
void tr_cold_start(const tr_model *m_, tr_data *d)
{
    const tr_model *m = TR_IN(m_, d);
    const int nf = tr_n_force(m), k = d->k;
    double straight[6], shaped[6], ra = INFINITY, rb = INFINITY;
    int c;
    cold_guess(m, d, d->x);
    for (c = 0; c < nf; c++) straight[c] = d->x[c];
    shape_guess(m, d, d->x);
    if (tr_residual(m, d, d->x, d->ft) == TR_OK) rb = tru_sumsq(d->ft, k);
    for (c = 0; c < nf; c++) {
        shaped[c] = d->x[c];
        d->x[c] = straight[c];
    }
    if (tr_residual(m, d, d->x, d->ft) == TR_OK) ra = tru_sumsq(d->ft, k);
    if (!(ra <= rb))
        for (c = 0; c < nf; c++) d->x[c] = shaped[c];
}

/* Node unknowns from a given base state (warm start): integrate from it; if the
 * trajectory runs away, fall back to the shape pass. */
static void init_nodes(const tr_model *m, tr_data *d, double *x)
{
    const int ns = m->n_states;
    double *y = d->y, tsum = 0.0;
    int k, j, ok = 1, c;
    if (m->nshoot <= 1) return;
    d->y_steps = -1; /* y becomes the node integration's state */
    d->rec = 0;
    tr_set_tensions(m, d, x);
    for (c = 0; c < m->nt; c++) tsum += d->tau[c] / m->F_s;
    tr_init_state(m, d, x, y, ns);
    for (k = 0; k < m->nseg && ok; k++) {
        const int b = k + 1;
        d->seg = k;
        if (tr_integrate(m, d, m->bp[k], m->bp[b], tr_segment_steps(m, d, k), y) != TR_OK) ok = 0;
        for (c = 0; c < m->n_base && ok; c++) {
            /* run away: position beyond 2 L, force/moment beyond 1e3 of the loads' scale */
            const double lim =
                (c < (m->planar ? 2 : 3)) ? 2.0 : 1e3 * (1.0 + tr_load_scale(m) + tsum);
            if (!(fabs(y[c]) / tr_node_scale(m, c) <= lim)) ok = 0;
        }
        if (ok && b < m->nseg) tr_apply_jump(m, d, b, y);
        if (ok && b < m->nseg && (j = m->bp_node[b]) > 0)
            for (c = 0; c < ns; c++) x[tr_node_off(m, j) + c] = y[c] / tr_node_scale(m, c);
    }
    if (!ok) {
        /* keep the given base unknowns */
        double base[6];
        for (c = 0; c < tr_n_force(m); c++) base[c] = x[c];
        shape_guess(m, d, x);
        for (c = 0; c < tr_n_force(m); c++) x[c] = base[c];
    }
}

/* ---------------------------------------------------------------- Newton */
/* int_0^T r_i . r_j ds for linear routings (body frame, straight robot). */
static double rr_integral(const tr_tendon *ti, const tr_tendon *tj, double T)
{
    const double cdp = ti->cphi * tj->cphi + ti->sphi * tj->sphi;
    return cdp * (ti->a * tj->a * T * T * T / 3.0 + 0.5 * (ti->a * tj->b + tj->a * ti->b) * T * T +
                  ti->b * tj->b * T);
}

/* q(s) = int_s^L (x - s) f_p(x) dx of the partial distributed forces f_p (world): the
 * moment of those distal of s about the straight centreline at s is e3 x q =
 * (-q_y, q_x, 0). */
static void pdist_first_moment(const tr_model *m, double s, double q[3])
{
    int k, c;
    q[0] = q[1] = q[2] = 0.0;
    for (k = 0; k < m->nseg; k++) {
        const double hi = m->bp[k + 1], lo = m->bp[k] > s ? m->bp[k] : s;
        double w;
        if (hi <= s) continue;
        w = 0.5 * ((hi - s) * (hi - s) - (lo - s) * (lo - s));
        for (c = 0; c < 3; c++) q[c] += w * m->seg_pdist[3 * k + c];
    }
}

/* int_0^T (m1 r_i2 - m2 r_i1) ds, m = moment of the loads distal of s about the
 * centreline of the straight robot (world = body): the path-length change the
 * loads alone cause is this / EI.  Integrands are polynomials of degree <= 3 in s on
 * each piece: 2-point Gauss-Legendre is exact. */
static double load_path_integral(const tr_model *m, const tr_data *d, const tr_tendon *ti, double T)
{
    const double gx[2] = {0.5 - 0.5 / sqrt(3.0), 0.5 + 0.5 / sqrt(3.0)};
    double sum = 0.0;
    int b, g;
    for (b = 1; b <= m->nseg; b++) {
        const double z = m->bp[b], top = z < T ? z : T;
        const double *F = m->bpF + 3 * b, *M = m->bpM + 3 * b;
        if (F[0] == 0.0 && F[1] == 0.0 && M[0] == 0.0 && M[1] == 0.0) continue;
        for (g = 0; g < 2; g++) {
            const double s = gx[g] * top, rho = ti->a * s + ti->b;
            const double m1 = -(z - s) * F[1] + M[0], m2 = (z - s) * F[0] + M[1];
            sum += 0.5 * top * (m1 * rho * ti->sphi - m2 * rho * ti->cphi);
        }
    }
    if (m->has_dist) {
        for (g = 0; g < 2; g++) {
            const double s = gx[g] * T, rho = ti->a * s + ti->b, h = 0.5 * (m->L - s) * (m->L - s);
            const double m1 = -h * m->dist[1], m2 = h * m->dist[0];
            sum += 0.5 * T * (m1 * rho * ti->sphi - m2 * rho * ti->cphi);
        }
    }
    if (m->has_pdist) {
        /* piecewise quadratic moment: 2-point Gauss on each segment below T */
        for (b = 0; b < m->nseg && m->bp[b] < T; b++) {
            const double lo = m->bp[b], hi = m->bp[b + 1] < T ? m->bp[b + 1] : T;
            for (g = 0; g < 2; g++) {
                const double s = lo + gx[g] * (hi - lo), rho = ti->a * s + ti->b;
                double q[3];
                pdist_first_moment(m, s, q);
                sum += 0.5 * (hi - lo) * (-q[1] * rho * ti->sphi - q[0] * rho * ti->cphi);
            }
        }
    }
    return d->lam_load * sum;
}

/* Cold guess: the base reaction from global balance of the straight robot (exact
 * for the force); the tensions from the small-deflection linear model about the
 * straight robot (docs/model.md, "links to the closed forms"):
 *   sum_j C_ij tau_j = q_i + (load term)_i - sum_{j tension-controlled} C_ij tau_j,
 *   C_ij = int r_i.r_j / EI + delta_ij t_i/EA_i + min(t_i, t_j)/EA_backbone,
 * with an active set for slack tendons (negative tension -> slack, re-solve); the
 * tensions are offsets from the pretensions.  If that system is singular (an
 * indeterminate set) each tendon gets its own diagonal estimate. */
static void cold_guess(const tr_model *m, tr_data *d, double *x)
{
    const int off = tr_n_force(m), nd = m->ndisp;
    double F[3] = {0, 0, 0}, M[3] = {0, 0, 0};
    double *C = d->lin_C, *A = d->lin_A, *rhs = d->lin_rhs, *sol = d->lin_sol;
    double *pre = d->lin_pre, *tmp = d->lin_tmp;
    int *act = d->lin_act, *map = d->lin_map;
    int i, j, b, c, round;
    memset(x, 0, (size_t)d->k * sizeof(double));
    for (b = 1; b <= m->nseg; b++) {
        const double s = m->bp[b];
        for (c = 0; c < 3; c++) {
            F[c] += m->bpF[3 * b + c];
            M[c] += m->bpM[3 * b + c];
        }
        /* s e3 x F = s (-Fy, Fx, 0) */
        M[0] += -s * m->bpF[3 * b + 1];
        M[1] += s * m->bpF[3 * b + 0];
    }
    for (c = 0; c < 3; c++) F[c] += m->L * m->dist[c];
    M[0] += -0.5 * m->L * m->L * m->dist[1];
    M[1] += 0.5 * m->L * m->L * m->dist[0];
    if (m->has_pdist) {
        double q[3];
        for (b = 0; b < m->nseg; b++)
            for (c = 0; c < 3; c++) F[c] += (m->bp[b + 1] - m->bp[b]) * m->seg_pdist[3 * b + c];
        pdist_first_moment(m, 0.0, q);
        M[0] += -q[1];
        M[1] += q[0];
    }
    for (c = 0; c < 3; c++) {
        F[c] *= d->lam_load;
        M[c] *= d->lam_load;
    }
    base_unknowns(m, F, M, x);
    if (nd == 0) return;
    /* the linear system over displacement-controlled tendons */
    for (i = 0; i < m->nt; i++) {
        const tr_tendon *ti = &m->tendon[i];
        int ii = ti->gamma_index;
        if (ti->control != TR_DISPLACEMENT) continue;
        rhs[ii] = d->lam_act * ti->value + load_path_integral(m, d, ti, ti->t) / m->EI;
        for (j = 0; j < m->nt; j++) {
            const tr_tendon *tj = &m->tendon[j];
            const double T = ti->t < tj->t ? ti->t : tj->t;
            double cij = rr_integral(ti, tj, T) / m->EI + (m->kirchhoff ? 0.0 : T / m->EA);
            if (i == j && isfinite(ti->EA)) cij += ti->t / ti->EA;
            if (tj->control == TR_DISPLACEMENT)
                C[ii * nd + tj->gamma_index] = cij;
            else
                rhs[ii] -= cij * d->lam_act * tj->value;
        }
        act[ii] = 1;
        pre[ii] = ti->pretension;
    }
    for (round = 0; round <= nd; round++) {
        int na = 0, neg = 0, ok;
        for (i = 0; i < nd; i++)
            if (act[i]) map[na++] = i;
        for (i = 0; i < na; i++) {
            for (j = 0; j < na; j++) A[i * na + j] = C[map[i] * nd + map[j]];
            sol[i] = rhs[map[i]];
        }
        ok = na == 0 || tru_solve_dense(na, A, sol) == 0;
        for (i = 0; ok && i < na; i++)
            if (!isfinite(sol[i]) || fabs(sol[i]) > 1e6 * m->tau_s) ok = 0;
        if (!ok) {
            /* singular: diagonal estimates */
            for (i = 0; i < nd; i++) {
                act[i] = C[i * nd + i] > 0.0 && rhs[i] > 0.0;
                sol[i] = act[i] ? rhs[i] / C[i * nd + i] : 0.0;
                map[i] = i;
            }
            na = nd;
            for (i = 0; i < nd; i++) tmp[i] = sol[i];
            for (i = 0; i < nd; i++) sol[i] = act[i] ? tmp[i] : 0.0;
            break;
        }
        /* scatter, drop the most negative tension */
        {
            double worst = 0.0;
            int wi = -1;
            for (i = 0; i < na; i++) {
                const double tau_i = pre[map[i]] + sol[i];
                if (tau_i < worst) {
                    worst = tau_i;
                    wi = map[i];
                }
            }
            if (wi >= 0) {
                act[wi] = 0;
                neg = 1;
            }
            for (i = 0; i < nd; i++) tmp[i] = 0.0;
            for (i = 0; i < na; i++) tmp[map[i]] = sol[i];
            for (i = 0; i < nd; i++) sol[i] = tmp[i];
        }
        if (!neg) break;
    }
    for (i = 0; i < m->nt; i++) {
        const tr_tendon *t = &m->tendon[i];
        const int ii = t->gamma_index;
        double tau;
        if (t->control != TR_DISPLACEMENT) continue;
        tau = t->pretension + (act[ii] ? sol[ii] : 0.0);
        if (tau > 0.0) {
            x[off + ii] = tr_gamma_of_tension(m, d->opt.slack_model, tau, 0.0);
        } else {
            /* slack = what the taut tendons leave of its constraint */
            double sl = -rhs[ii];
            for (j = 0; j < nd; j++) sl += C[ii * nd + j] * (act[j] ? sol[j] : 0.0);
            x[off + ii] = tr_gamma_of_tension(m, d->opt.slack_model, 0.0, sl);
        }
    }
}

/* The guess <-> unknowns map.  A physical guess g is [n(0) world (3), m(0) world (3),
 * tension (nt) [N], slack (nt) [m]] with n(0), m(0) the internal force and moment of
 * the backbone at the base; the unknowns are the base reaction of the whole section
 * (backbone plus the tendon pulls, see tr_tendon_pull_sum), scaled, and the gammas. */
int tr_unknowns_from_guess(const tr_model *m_, tr_data *d, const double *g, double *x)
{
    const tr_model *m = TR_IN(m_, d);
    const int k = d->k, off = tr_n_force(m);
    double tn[3], tm[3];
    int i;
    tr_tendon_pull_sum(m, g + 6, tn, tm);
    for (i = 0; i < 3; i++) {
        tn[i] += g[i];
        tm[i] += g[3 + i];
    }
    base_unknowns(m, tn, tm, x);
    for (i = 0; i < m->nt; i++) {
        const tr_tendon *t = &m->tendon[i];
        if (t->control != TR_DISPLACEMENT) continue;
        x[off + t->gamma_index] =
            tr_gamma_of_tension(m, d->opt.slack_model, g[6 + i], g[6 + m->nt + i]);
    }
    for (i = 0; i < k; i++)
        if (!isfinite(x[i])) {
            tr_set_message(d, "guess contains a non-finite value");
            return TR_EINVAL;
        }
    init_nodes(m, d, x);
    return TR_OK;
}

void tr_base_state(const tr_model *m_, const tr_data *d, double *g)
{
    const tr_model *m = TR_IN(m_, d);
    const int off = tr_n_force(m), nt = m->nt;
    const double *x = d->x;
    double tn[3], tm[3];
    int i, c;
    for (i = 0; i < nt; i++) {
        const tr_tendon *t = &m->tendon[i];
        if (t->control == TR_DISPLACEMENT) {
            tr_tension_of_gamma(m, d->opt.slack_model, x[off + t->gamma_index], g + 6 + i,
                                g + 6 + nt + i);
        } else {
            g[6 + i] = t->value;
            g[6 + nt + i] = 0.0;
        }
    }
    tr_tendon_pull_sum(m, g + 6, tn, tm);
    if (m->planar) {
        g[0] = x[0] * m->F_s - tn[0];
        g[1] = 0.0;
        g[2] = x[1] * m->F_s - tn[2];
        g[3] = 0.0;
        g[4] = x[2] * m->M_s - tm[1];
        g[5] = 0.0;
    } else {
        for (c = 0; c < 3; c++) {
            g[c] = x[c] * m->F_s - tn[c];
            g[3 + c] = x[3 + c] * m->M_s - tm[c];
        }
    }
}
