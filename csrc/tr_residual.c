/*
 * tr_residual.c -- the shooting residual (docs/model.md).
 *
 * Unknowns (scaled): the base reaction of backbone plus tendons,
 *   (n(0) + sum tau_i t0_i) / (EI/L^2),  (m(0) + sum tau_i r_i(0) x t0_i) / (EI/L)
 * (t0_i: tendon tangent of the straight robot; planar: x, z force and y moment),
 * which global balance fixes (nearly) independently of the tensions, so the
 * tension unknowns do not fight the backbone force; then one gamma per
 * displacement-controlled tendon (see tr_tension_of_gamma); then, with multiple
 * shooting, the full state at each interior shooting node.
 * Residuals (scaled): tip force / (EI/L^2) and moment / (EI/L), body frame, the
 * length constraints E_i / l_s with
 *   E_i = s_i(t_i) + q_i + slack_i - (1 + tau_i/EA_i) rest_i
 * (the path length is integrated as its excess over the reference length, which
 * keeps the digits that stiff tendons need), and the continuity of the state at the
 * shooting nodes.  And the forward difference of the residual along one unknown (a
 * column of the finite-difference Jacobian; tr_newton.c, tr_hybrid.c, tr_path.c).
 */
#include <math.h>
#include <string.h>

#include "tendonrod.h"
#include "tr_internal.h"
#include "tru_math.h"

/* Tensions and slacks of the unknowns x: from each displacement-controlled tendon's
 * gamma, and the prescribed tension (scaled by the actuation continuation
 * parameter) of the others. */
void tr_set_tensions(const tr_model *m_, tr_data *d, const double *x)
{
    const tr_model *m = TR_IN(m_, d);
    const int off = tr_n_force(m);
    int i;
    for (i = 0; i < m->nt; i++) {
        const tr_tendon *t = &m->tendon[i];
        if (t->control == TR_DISPLACEMENT) {
            tr_tension_of_gamma(m, d->opt.slack_model, x[off + t->gamma_index], &d->tau[i],
                                &d->beta[i]);
        } else {
            d->tau[i] = d->lam_act * t->value;
            d->beta[i] = 0.0;
        }
    }
}

/* Base state from the unknowns (tensions already set): the backbone carries the
 * base reaction minus the tendon pulls. */
void tr_init_state(const tr_model *m_, const tr_data *d, const double *x, double *y, int dim)
{
    const tr_model *m = TR_IN(m_, d);
    double tn[3], tm[3];
    int i;
    tr_tendon_pull_sum(m, d->tau, tn, tm);
    memset(y, 0, (size_t)dim * sizeof(double));
    if (m->planar) {
        y[TR_YP_N1] = x[0] * m->F_s - tn[0];
        y[TR_YP_N3] = x[1] * m->F_s - tn[2];
        y[TR_YP_M] = x[2] * m->M_s - tm[1];
    } else {
        y[TR_Y_R + 0] = y[TR_Y_R + 4] = y[TR_Y_R + 8] = 1.0;
        for (i = 0; i < 3; i++) {
            y[TR_Y_N + i] = x[i] * m->F_s - tn[i];
            y[TR_Y_M + i] = x[3 + i] * m->M_s - tm[i];
        }
    }
}

/* Loads at breakpoint b (world): point loads scaled by lam_load, plus the probe (scaled
 * by 1 - lam_imp while an imperfection is removed). */
static void bp_load(const tr_model *m, const tr_data *d, int b, double F[3], double M[3])
{
    int c;
    for (c = 0; c < 3; c++) {
        F[c] = d->lam_load * m->bpF[3 * b + c];
        M[c] = d->lam_load * m->bpM[3 * b + c];
    }
    if (b == d->probe_bp)
        for (c = 0; c < 3; c++) {
            F[c] += (1.0 - d->lam_imp) * d->probe[c];
            M[c] += (1.0 - d->lam_imp) * d->probe[3 + c];
        }
}

/* Sum of the anchor pulls of the tendons anchored at breakpoint b, body frame:
 * force sum tau t^, moment sum tau r x t^ (state just proximal of b). */
static void anchor_sum(const tr_model *m, const tr_data *d, int b, const double *y, double fn[3],
                       double fm[3])
{
    const double s = m->bp[b];
    int i;
    fn[0] = fn[1] = fn[2] = fm[0] = fm[1] = fm[2] = 0.0;
    for (i = 0; i < m->nt; i++) {
        double th[3], r[3], rt[3];
        const double tau = tr_tension_at(m, d, i, y);
        if (m->tendon[i].end_bp != b || !(tau > 0.0)) continue;
        tr_tendon_tangent(m, i, s, y, th, r);
        tru_cross3(rt, r, th);
        fn[0] += tau * th[0];
        fn[1] += tau * th[1];
        fn[2] += tau * th[2];
        fm[0] += tau * rt[0];
        fm[1] += tau * rt[1];
        fm[2] += tau * rt[2];
    }
}

/* Jump at interior breakpoint b.  The whole section (backbone plus tendons)
 * carries the external load: its force and moment jump by the point load,
 *   n_b+ + sum_cont tau t^+ = n_b- + sum_all tau t^- - R^T P    (moments alike),
 * where "all" are the tendons active before b (those anchored at b hand their
 * pull to the backbone) and "cont" those continuing past it.  Where the jump
 * changes the strains (a Cosserat rod under a point force, any rod under a point
 * moment or an anchor), the continuing tendons kink and push on the backbone;
 * t^+ depends on n_b+, m_b+, so this is a small Newton solve with the matrix of
 * the right-hand side. */
void tr_apply_jump(const tr_model *m_, const tr_data *d, int b, double *y)
{
    const tr_model *m = TR_IN(m_, d);
    const double s = m->bp[b];
    double F[3], M[3], Fb[3], Mb[3], nb[3], mb[3], fn[3], fm[3], Cn[3], Cm[3];
    const double *tau = tr_tensions_at(m, d, y); /* continuous across the breakpoint */
    int c, it;
    bp_load(m, d, b, F, M);
    if (m->planar) {
        const double ct = cos(y[TR_YP_TH]), st = sin(y[TR_YP_TH]);
        Fb[0] = ct * F[0] - st * F[2];
        Fb[1] = 0.0;
        Fb[2] = st * F[0] + ct * F[2];
        Mb[0] = 0.0;
        Mb[1] = M[1];
        Mb[2] = 0.0;
        nb[0] = y[TR_YP_N1];
        nb[1] = 0.0;
        nb[2] = y[TR_YP_N3];
        mb[0] = 0.0;
        mb[1] = y[TR_YP_M];
        mb[2] = 0.0;
    } else {
        tru_mattvec3(Fb, y + TR_Y_R, F);
        tru_mattvec3(Mb, y + TR_Y_R, M);
        memcpy(nb, y + TR_Y_N, sizeof nb);
        memcpy(mb, y + TR_Y_M, sizeof mb);
    }
    tr_section_pulls(m, tau, b - 1, s, nb, mb, fn, fm, NULL);
    for (c = 0; c < 3; c++) {
        Cn[c] = nb[c] + fn[c] - Fb[c];
        Cm[c] = mb[c] + fm[c] - Mb[c];
    }
    /* first guess: the continuing tendons keep their direction */
    tr_section_pulls(m, tau, b, s, nb, mb, fn, fm, NULL);
    for (c = 0; c < 3; c++) {
        nb[c] = Cn[c] - fn[c];
        mb[c] = Cm[c] - fm[c];
    }
    for (it = 0; it < TR_JUMP_ITER; it++) {
        double J6[36], g[6], gmax = 0.0, scale = 0.0;
        tr_section_pulls(m, tau, b, s, nb, mb, fn, fm, J6);
        for (c = 0; c < 3; c++) {
            g[c] = -(nb[c] + fn[c] - Cn[c]) / m->F_s;
            g[3 + c] = -(mb[c] + fm[c] - Cm[c]) / m->M_s;
            scale += fabs(Cn[c]) / m->F_s + fabs(Cm[c]) / m->M_s + fabs(fn[c]) / m->F_s;
        }
        for (c = 0; c < 6; c++)
            if (fabs(g[c]) > gmax) gmax = fabs(g[c]);
        if (gmax <= 1e-15 * (1.0 + scale)) break;
        /* (I + J6) dx = g in scaled units: columns of J6 times the unknowns' scales */
        {
            double Mx[36];
            int r_, c_;
            for (r_ = 0; r_ < 6; r_++)
                for (c_ = 0; c_ < 6; c_++) {
                    const double rs = r_ < 3 ? m->F_s : m->M_s, cs = c_ < 3 ? m->F_s : m->M_s;
                    Mx[6 * r_ + c_] = (r_ == c_) + J6[6 * r_ + c_] * cs / rs;
                }
            if (tru_solve_dense(6, Mx, g) != 0) break;
        }
        for (c = 0; c < 3; c++) {
            nb[c] += g[c] * m->F_s;
            mb[c] += g[3 + c] * m->M_s;
        }
    }
    if (m->planar) {
        y[TR_YP_N1] = nb[0];
        y[TR_YP_N3] = nb[2];
        y[TR_YP_M] = mb[1];
    } else {
        memcpy(y + TR_Y_N, nb, sizeof nb);
        memcpy(y + TR_Y_M, mb, sizeof mb);
    }
}

/* A linearisation's record of the pose at breakpoint b (before its jump). */
static void capture_pose(const tr_model *m, tr_data *d, int b, const double *y)
{
    double n[3], mo[3], *pose = d->capture + 12 * b;
    tr_state_world(m, y, pose, pose + 3, n, mo);
}

/* Tip residual (scaled) into f. */
static void tip_residual(const tr_model *m, tr_data *d, const double *y, double *f)
{
    double F[3], M[3], fn[3], fm[3];
    const int off = tr_n_force(m);
    const int lenbase = m->planar ? TR_YP_LEN : TR_Y_LEN;
    int i;
    bp_load(m, d, m->nseg, F, M);
    anchor_sum(m, d, m->nseg, y, fn, fm);
    if (m->planar) {
        const double c = cos(y[TR_YP_TH]), s = sin(y[TR_YP_TH]);
        f[0] = (y[TR_YP_N1] + fn[0] - (c * F[0] - s * F[2])) / m->F_s;
        f[1] = (y[TR_YP_N3] + fn[2] - (s * F[0] + c * F[2])) / m->F_s;
        f[2] = (y[TR_YP_M] + fm[1] - M[1]) / m->M_s;
    } else {
        double Fb[3], Mb[3];
        int c;
        tru_mattvec3(Fb, y + TR_Y_R, F);
        tru_mattvec3(Mb, y + TR_Y_R, M);
        for (c = 0; c < 3; c++) {
            f[c] = (y[TR_Y_N + c] + fn[c] - Fb[c]) / m->F_s;
            f[3 + c] = (y[TR_Y_M + c] + fm[c] - Mb[c]) / m->M_s;
        }
    }
    for (i = 0; i < m->nt; i++) {
        const tr_tendon *t = &m->tendon[i];
        double E;
        if (t->control != TR_DISPLACEMENT) continue;
        if (t->target_row >= 0) {
            f[off + t->gamma_index] = tr_target_residual(m, y, t->target_row);
            continue;
        }
        /* s_i - (1 + tau/EA) rest with s_i = sref + excess, rest = sref + rest_dev */
        E = y[lenbase + (d->rec ? i : t->len_index)] + d->lam_act * t->value + d->beta[i] -
            t->rest_dev - (isfinite(t->EA) ? d->tau[i] / (t->EA * d->ea_scale) : 0.0) * t->rest;
        f[off + t->gamma_index] = E / m->len_s;
    }
}

/* Magnitude of all external loads, scaled by EI/L^2 (forces) and EI/L (moments). */
double tr_load_scale(const tr_model *m)
{
    double F = m->L * tru_norm3(m->dist) / m->F_s;
    int b;
    for (b = 1; b <= m->nseg; b++)
        F += tru_norm3(m->bpF + 3 * b) / m->F_s + tru_norm3(m->bpM + 3 * b) / m->M_s;
    if (m->has_pdist)
        for (b = 0; b < m->nseg; b++)
            F += (m->bp[b + 1] - m->bp[b]) * tru_norm3(m->seg_pdist + 3 * b) / m->F_s;
    return F;
}

/* Offset of shooting node j (1..M-1) in the unknowns and in the residuals. */
int tr_node_off(const tr_model *m, int j)
{
    return tr_n_force(m) + m->ndisp + (j - 1) * m->n_states;
}

double tr_node_scale(const tr_model *m, int c)
{
    return c < m->n_base ? m->xstate_scale[c] : c < m->n_base + m->ndisp ? m->len_s : m->tau_s;
}

/* At shooting node j: continuity residual (integrated minus unknown, scaled) into f
 * (if f != NULL), then restart from the unknown state. */
static void node_restart(const tr_model *m, const double *x, int j, double *y, double *f)
{
    const int o = tr_node_off(m, j), ns = m->n_states;
    int c;
    for (c = 0; c < ns; c++) {
        const double sc = tr_node_scale(m, c);
        if (f) f[o + c] = y[c] / sc - x[o + c];
        y[c] = x[o + c] * sc;
    }
}

int tr_holds_end_state(const tr_data *d, const double *x)
{
    return d->y_steps == d->steps && memcmp(d->x_of_y, x, (size_t)d->k * sizeof(double)) == 0;
}

void tr_restore_end_state(const tr_model *m_, tr_data *d, const double *x, const double *f)
{
    const tr_model *m = TR_IN(m_, d);
    memcpy(d->y, d->ysave, (size_t)m->n_states * sizeof(double));
    memcpy(d->x_of_y, x, (size_t)d->k * sizeof(double));
    memcpy(d->f_of_y, f, (size_t)d->k * sizeof(double));
    d->y_steps = d->steps;
}

int tr_residual(const tr_model *m_, tr_data *d, const double *x, double *f)
{
    const tr_model *m = TR_IN(m_, d);
    int k, status;
    double *y = d->y;
    d->rec = 0;
    d->nfev++;
    d->y_steps = -1;
    tr_set_tensions(m, d, x);
    tr_init_state(m, d, x, y, m->n_states);
    for (k = 0; k < m->nseg; k++) {
        d->seg = k;
        status = tr_integrate(m, d, m->bp[k], m->bp[k + 1], tr_segment_steps(m, d, k), y);
        if (status != TR_OK) return status;
        if (d->capture) capture_pose(m, d, k + 1, y);
        if (k + 1 < m->nseg) {
            tr_apply_jump(m, d, k + 1, y);
            if (m->bp_node[k + 1] > 0) node_restart(m, x, m->bp_node[k + 1], y, f);
        }
    }
    tip_residual(m, d, y, f);
    if (d->lam_hom != 1.0) /* continuation from the guess */
        for (k = 0; k < d->k; k++) f[k] -= (1.0 - d->lam_hom) * d->f_guess[k];
    if (!isfinite(tru_maxnorm(f, d->k))) return TR_ENONFINITE;
    if (!d->steps_double && d->probe_bp < 0 && !d->capture && d->lam_act == 1.0 &&
        d->lam_load == 1.0 && d->lam_hom == 1.0) {
        /* y is the end state of the solution with unknowns x at d->steps */
        memcpy(d->x_of_y, x, (size_t)d->k * sizeof(double));
        memcpy(d->f_of_y, f, (size_t)d->k * sizeof(double));
        d->y_steps = d->steps;
    }
    return TR_OK;
}

/* 1 when unknown j is a tendon's tension/slack unknown gamma on its slack side (< 0). */
static int on_slack_side(const tr_model *m, const double *x, int j)
{
    const int g = j - tr_n_force(m);
    int i;
    if (g < 0 || !(x[j] < 0.0)) return 0;
    for (i = 0; i < m->nt; i++)
        if (m->tendon[i].gamma_index == g) return 1;
    return 0;
}

int tr_fd_column(const tr_model *m_, tr_data *d, const double *x, const double *f0, int j,
                 double *col, size_t stride, int backward)
{
    const tr_model *m = TR_IN(m_, d);
    const int k = d->k;
    int i, status;
    double h = TR_FD_H * (fabs(x[j]) > 1.0 ? fabs(x[j]) : 1.0);
    /* a tendon's gamma is differenced on the side of its taut/slack switch it is on: the
     * residual is kinked there, and a difference across the kink is neither side's
     * derivative (Newton then creeps toward a root at the switch) */
    if (on_slack_side(m, x, j)) h = -h;
    memcpy(d->xt, x, (size_t)k * sizeof(double));
    d->xt[j] += h;
    h = d->xt[j] - x[j];
    status = tr_residual(m, d, d->xt, d->ft);
    if (status != TR_OK) {
        if (!backward || d->stop) return status;
        d->xt[j] = x[j] - h;
        status = tr_residual(m, d, d->xt, d->ft);
        if (status != TR_OK) return status;
        h = -h;
    }
    for (i = 0; i < k; i++) col[i * stride] = (d->ft[i] - f0[i]) / h;
    return TR_OK;
}
