/*
 * tr_newton.c -- the Newton layer: finite-difference Jacobian, LU, good-Broyden
 * update, init / iterate / test with a backtracking (Armijo) line search, the run
 * to convergence with a stagnation test, and the lean warm solve.
 */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <gsl/gsl_errno.h>

#include "tendonrod.h"
#include "tr_internal.h"
#include "tru_math.h"

void tr_solve_reset(const tr_model *m_, tr_data *d, int steps)
{
    const tr_model *m = TR_IN(m_, d);
    (void)m;
    d->nit = d->nfev = d->njev = d->cont_steps = 0;
    d->steps_moved = 0;
    d->steps_double = 0;
    d->message[0] = '\0';
    d->lam_act = d->lam_load = d->lam_hom = d->lam_fric = 1.0;
    d->lam_imp = 0.0;
    d->ea_scale = 1.0;
    d->via_path = d->ramp_stable = 0;
    d->tip_guess[0] = d->tip_guess[1] = d->tip_guess[2] = NAN;
    d->truncation = NAN;
    d->jacobian_cond = NAN;
    d->tip_angle = NAN;
    d->probe_bp = -1;
    d->steps = steps;
    d->jac_method = d->opt.jacobian_method;
    d->nfev_confirm = 0;
    d->stable = d->stab_index = -1;
    d->stab_kept = 0;
    d->stability = NAN;
    d->stab_gap = 0.0;
    d->branch_note[0] = '\0';
    snprintf(d->stab_reason, sizeof d->stab_reason, "not tested: no solution");
    tr_poll_start(d);
}

double tr_shared_weight(const tr_model *m, int i)
{
    /* w = 1 - R^T (R R^T)^+ R 1, R = [offset vectors at the base] (2 x n) */
    double A[3] = {0, 0, 0}, b[2] = {0, 0}, r[2], l1, l2, c, sn, y1, y2, n1, n2, w;
    int j;
    if (m->tendon[i].control != TR_DISPLACEMENT) return 0.0;
    for (j = 0; j < m->nt; j++) {
        const tr_tendon *t = m->tendon + j;
        if (t->control != TR_DISPLACEMENT) continue;
        r[0] = t->b * t->cphi;
        r[1] = t->b * t->sphi;
        A[0] += r[0] * r[0];
        A[1] += r[0] * r[1];
        A[2] += r[1] * r[1];
        b[0] += r[0];
        b[1] += r[1];
    }
    /* eigen-decomposition of the 2 x 2 [A0 A1; A1 A2]: pseudo-inverse applied to b */
    {
        const double tr = A[0] + A[2], det = A[0] * A[2] - A[1] * A[1];
        const double disc = sqrt(fmax(0.25 * tr * tr - det, 0.0));
        const double th = 0.5 * atan2(2.0 * A[1], A[0] - A[2]);
        l1 = 0.5 * tr + disc;
        l2 = 0.5 * tr - disc;
        c = cos(th);
        sn = sin(th);
    }
    n1 = c * b[0] + sn * b[1];
    n2 = -sn * b[0] + c * b[1];
    y1 = l1 > 1e-12 * (l1 + l2) && l1 > 0.0 ? n1 / l1 : 0.0;
    y2 = l2 > 1e-12 * (l1 + l2) && l2 > 0.0 ? n2 / l2 : 0.0;
    r[0] = m->tendon[i].b * m->tendon[i].cphi;
    r[1] = m->tendon[i].b * m->tendon[i].sphi;
    w = 1.0 - ((c * r[0] + sn * r[1]) * y1 + (-sn * r[0] + c * r[1]) * y2);
    return fabs(w) > 1e-9 ? w : 0.0;
}

/* The Jacobian along the shared tension direction c, replaced by a difference of its own
 * (a rank-1 correction J += (J_c - J c) c^T / c^T c); also the largest tension unknown,
 * for the step cap. */
static int shared_column(const tr_model *m, tr_data *d)
{
    const int k = d->k, off = tr_n_force(m);
    double cc = 0.0, gmax = 0.0, h;
    int i, j, st;
    for (i = 0; i < m->nt; i++) {
        const tr_tendon *t = m->tendon + i;
        const double w = tr_shared_weight(m, i);
        if (t->gamma_index < 0) continue;
        cc += w * w;
        if (fabs(d->x[off + t->gamma_index]) > gmax) gmax = fabs(d->x[off + t->gamma_index]);
    }
    if (!(cc > 0.0)) return TR_OK;
    h = TR_SHARED_H * (gmax > 1.0 ? gmax : 1.0);
    memcpy(d->xt, d->x, (size_t)k * sizeof(double));
    for (i = 0; i < m->nt; i++)
        if (m->tendon[i].gamma_index >= 0)
            d->xt[off + m->tendon[i].gamma_index] += h * tr_shared_weight(m, i);
    st = tr_residual(m, d, d->xt, d->ft);
    if (st != TR_OK) return st;
    for (i = 0; i < k; i++) {
        double jc = 0.0, corr;
        for (j = 0; j < m->nt; j++)
            if (m->tendon[j].gamma_index >= 0)
                jc += d->J[i * k + off + m->tendon[j].gamma_index] * tr_shared_weight(m, j);
        corr = ((d->ft[i] - d->f[i]) / h - jc) / cc;
        for (j = 0; j < m->nt; j++)
            if (m->tendon[j].gamma_index >= 0)
                d->J[i * k + off + m->tendon[j].gamma_index] += corr * tr_shared_weight(m, j);
    }
    return TR_OK;
}

double tr_shared_resolution(const tr_model *m_, tr_data *d)
{
    const tr_model *m = TR_IN(m_, d);
    const int k = d->k, off = tr_n_force(m);
    double gmax = 0.0, h, jc = 0.0, dtau, dg;
    int i;
    if (tr_residual(m, d, d->x, d->f) != TR_OK) return NAN;
    d->fnorm = tru_maxnorm(d->f, k);
    for (i = 0; i < m->nt; i++) {
        const int g = m->tendon[i].gamma_index;
        if (g >= 0 && fabs(d->x[off + g]) > gmax) gmax = fabs(d->x[off + g]);
    }
    h = TR_SHARED_H * (gmax > 1.0 ? gmax : 1.0);
    memcpy(d->xt, d->x, (size_t)k * sizeof(double));
    for (i = 0; i < m->nt; i++)
        if (m->tendon[i].gamma_index >= 0)
            d->xt[off + m->tendon[i].gamma_index] += h * tr_shared_weight(m, i);
    if (tr_residual(m, d, d->xt, d->ft) != TR_OK) return NAN;
    for (i = 0; i < k; i++) {
        const double e = fabs(d->ft[i] - d->f[i]) / h;
        if (e > jc) jc = e;
    }
    /* the residual reached, or its rounding level (~1e-13 scaled, measured on stiff
     * scenes) if lower: the level can sit anywhere its residuals do not tell apart */
    dg = (d->fnorm > TR_RESIDUAL_NOISE ? d->fnorm : TR_RESIDUAL_NOISE) / jc;
    tr_tension_of_gamma(m, TR_SLACK_LINEAR, dg, &dtau, &h);
    return dtau;
}

int tr_fd_jacobian(const tr_model *m_, tr_data *d)
{
    const tr_model *m = TR_IN(m_, d);
    const int k = d->k;
    /* the end state of the solution, if y holds it, survives the perturbed evaluations */
    const int keep = tr_holds_end_state(d, d->x);
    int j, status;
    if (d->nfev + k > d->opt.max_nfev) {
        tr_set_message(d,
                       "function-evaluation limit (max_nfev = %d) reached: a Jacobian needs %d "
                       "more evaluations; raise max_nfev",
                       d->opt.max_nfev, k);
        return TR_EMAXFEV;
    }
    for (j = 0; j < k; j++) {
        /* a column whose forward trial leaves the finite domain is taken backwards */
        if (j == 0 && keep) memcpy(d->ysave, d->y, (size_t)m->n_states * sizeof(double));
        status = tr_fd_column(m, d, d->x, d->f, j, d->J + j, (size_t)k, 1);
        if (status != TR_OK) return status;
    }
    if (d->shared_mode) {
        status = shared_column(m, d);
        if (status != TR_OK) return status;
    }
    if (keep) tr_restore_end_state(m, d, d->x, d->f);
    memcpy(d->x_J, d->x, (size_t)k * sizeof(double));
    d->steps_J = d->steps;
    d->njev++;
    d->have_J = 1;
    d->J_fresh = 1;
    d->J_refresh = 0;
    return TR_OK;
}

int tr_lu_factor(tr_data *d)
{
    const int k = d->k;
    int i, signum;
    double dmax = 0.0, dmin = INFINITY;
    /* a factorisation the budget cannot pay for is not started (one of 1,140 unknowns
     * takes ~1.3 s here, beyond any check inside it) */
    long nnz = 0;
    double cost;
    if (tr_poll(d)) return -1;
    for (i = 0; i < k * k; i++) nnz += d->J[i] != 0.0;
    cost = tr_lu_work(k, k > 0 ? (double)nnz / ((double)k * k) : 1.0);
    if (!d->finishing && d->spent + cost > tr_work_budget(d)) {
        d->stop = TR_EBUDGET;
        return -1;
    }
    d->spent += cost;
    memcpy(d->LU, d->J, (size_t)k * k * sizeof(double));
    tru_lu_factor(k, d->LU, k, d->piv, &signum);
    d->lu_sign = signum;
    for (i = 0; i < k; i++) {
        const double a = fabs(d->LU[(size_t)i * k + i]);
        if (!isfinite(a)) return -1;
        if (a > dmax) dmax = a;
        if (a < dmin) dmin = a;
    }
    if (!(dmin > 1e-300) || !(dmin > 1e-15 * dmax) || !isfinite(dmax)) return -1;
    return 0;
}

int tr_lu_solve(tr_data *d, const double *rhs, double *res)
{
    d->spent += tr_trsv_work(d->k);
    if (res != rhs) memcpy(res, rhs, (size_t)d->k * sizeof(double));
    tru_lu_solve(d->k, d->LU, d->k, d->piv, res);
    return 0;
}

/* J^T res = rhs from the factors P J = L U: U^T L^T (P res) = rhs. */
static int lu_solve_trans(tr_data *d, const double *rhs, double *res)
{
    d->spent += tr_trsv_work(d->k);
    if (res != rhs) memcpy(res, rhs, (size_t)d->k * sizeof(double));
    tru_lu_solve_trans(d->k, d->LU, d->k, d->piv, res);
    return 0;
}

static double norm1(const double *v, int k)
{
    double s = 0.0;
    int i;
    for (i = 0; i < k; i++) s += fabs(v[i]);
    return s;
}

/* |J^-1|_1 from the LU factors: Higham's refinement of Hager's estimator (LAPACK's
 * dlacon, Higham 1988, Algorithm 4.1): at most TR_COND_EST_ITERS pairs of solves with J
 * and J^T, and one more with an alternating test vector; a lower bound, within a small
 * factor of the true norm in practice.  NAN if a solve fails. */
static double inverse_norm1(tr_data *d)
{
    const int k = d->k;
    double *x = d->work, *y = d->ft, *z = d->fs, *xi = d->xp;
    double est = 0.0, alt;
    int i, it, jmax = 0;
    for (i = 0; i < k; i++) x[i] = 1.0 / k;
    for (it = 0;; it++) {
        double zmax = -1.0, e;
        int same = it > 0, jprev = jmax;
        if (tr_lu_solve(d, x, y) != 0) return NAN;
        e = norm1(y, k);
        if (it > 0 && !(e > est)) break; /* no increase: the estimate stands */
        est = e;
        for (i = 0; i < k; i++) {
            const double sg = y[i] >= 0.0 ? 1.0 : -1.0;
            if (sg != xi[i]) same = 0;
            xi[i] = sg;
        }
        if (same || it + 1 >= TR_COND_EST_ITERS) break; /* the same signs: a local maximum */
        if (lu_solve_trans(d, xi, z) != 0) return NAN;
        for (i = 0; i < k; i++)
            if (fabs(z[i]) > zmax) {
                zmax = fabs(z[i]);
                jmax = i;
            }
        if (it > 0 && fabs(z[jprev]) >= zmax) break; /* no better column: converged */
        for (i = 0; i < k; i++) x[i] = (i == jmax);
    }
    /* the alternating vector catches what the iteration misses (Higham 1988) */
    for (i = 0; i < k; i++)
        x[i] = (i % 2 ? -1.0 : 1.0) * (1.0 + (k > 1 ? (double)i / (k - 1) : 0.0));
    if (tr_lu_solve(d, x, y) != 0) return NAN;
    alt = 2.0 * norm1(y, k) / (3.0 * k);
    return alt > est ? alt : est;
}

double tr_jacobian_cond(tr_data *d)
{
    const int k = d->k;
    double nJ = 0.0, nI;
    int i, j;
    if (k == 0) return 1.0;
    for (j = 0; j < k; j++) {
        double c = 0.0;
        for (i = 0; i < k; i++) c += fabs(d->J[i * k + j]);
        if (c > nJ) nJ = c;
    }
    if (tr_lu_factor(d) != 0) return d->stop ? NAN : INFINITY;
    nI = inverse_norm1(d);
    return isnan(nI) ? (d->stop ? NAN : INFINITY) : nJ * nI;
}

/* Good Broyden update of the k x k row-major J after the step s (|s|^2 = ss) took
 * the residual from f to ft: J += (ft - f - J s) s^T / (s^T s). */
static void broyden_update(int k, double *J, const double *s, double ss, const double *f,
                           const double *ft)
{
    int i, j;
    for (i = 0; i < k; i++) {
        double r = ft[i] - f[i];
        for (j = 0; j < k; j++) r -= J[i * k + j] * s[j];
        r /= ss;
        for (j = 0; j < k; j++) J[i * k + j] += r * s[j];
    }
}

int tr_solve_init(const tr_model *m_, tr_data *d, const double *guess, const double *jac)
{
    const tr_model *m = TR_IN(m_, d);
    const int k = d->k;
    int i, status;
    if (!TR_OWNS(m, d)) {
        tr_set_message(d, "workspace was allocated for a different model");
        return TR_EINVAL;
    }
    if (guess) {
        status = tr_unknowns_from_guess(m, d, guess, d->x);
        if (status != TR_OK) return status;
    } else {
        tr_cold_start(m, d);
    }
    d->have_J = d->J_fresh = d->J_refresh = 0;
    if (jac) {
        memcpy(d->J, jac, (size_t)k * k * sizeof(double));
        d->have_J = 1;
        for (i = 0; i < k * k; i++)
            if (!isfinite(jac[i])) d->have_J = 0;
    }
    status = tr_residual(m, d, d->x, d->f);
    d->fnorm = tru_maxnorm(d->f, k);
    if (status != TR_OK)
        tr_set_message(d, "the residual at the starting point is not finite (it is far from "
                          "any equilibrium); try a guess from a nearby scene (or none, if one "
                          "was given)");
    return status;
}

/* The round-off floor of the scaled residual at the current iterate: the unit round-off
 * times the largest terms the residual sums.  The tip force is the backbone's internal
 * force plus the tendons' pulls minus the load, and the backbone carries the tendons' pull
 * back to the base, so its force is of the order of the tensions' sum however small the
 * load: rounded along the integration at that size (then turned into every component by
 * the curvature), it leaves a noise of eps sum|tau| / (EI/L^2) in the force residuals and
 * eps sum|tau_i| r_i / (EI/L) in the moment ones (r_i the tendon's largest offset), beside
 * eps times the base reaction and the loads (scaled).  The length residuals are
 * differences of lengths of the order of L, their noise eps L / r_max far below. */
double tr_roundoff_floor(const tr_model *m_, const tr_data *d)
{
    const tr_model *m = TR_IN(m_, d);
    double tau = 0.0, taur = 0.0, big = tr_load_scale(m), len = m->L / m->len_s;
    int i;
    for (i = 0; i < m->nt; i++) {
        const tr_tendon *t = m->tendon + i;
        const double r = t->route == TR_ROUTE_LINEAR ? fabs(t->b) + fabs(t->a) * t->t : m->len_s;
        if (!isfinite(d->tau[i])) continue;
        tau += fabs(d->tau[i]);
        taur += fabs(d->tau[i]) * r;
    }
    for (i = 0; i < tr_n_force(m); i++)
        if (fabs(d->x[i]) > big) big = fabs(d->x[i]);
    big += tau / m->F_s > taur / m->M_s ? tau / m->F_s : taur / m->M_s;
    return DBL_EPSILON * (big > len ? big : len);
}

/* tol, or the residual's round-off floor where that is below TR_ROUNDOFF_HINT (a floor
 * above it leaves no digits worth the name: such a scene fails as it did). */
int tr_solve_test(const tr_model *m_, const tr_data *d)
{
    const tr_model *m = TR_IN(m_, d);
    const double fl = tr_roundoff_floor(m, d);
    return d->fnorm <= tr_tol(d) || (d->fnorm <= fl && fl <= TR_ROUNDOFF_HINT) ? TR_OK
                                                                               : TR_CONTINUE;
}

/* Backtracking line search along d->dx from d->x: the first alpha with the Armijo
 * decrease of |f|^2 puts the trial point in d->xt, d->ft and returns 1; with a
 * Broyden (not fresh) Jacobian the first failure asks for a fresh one (returns 0,
 * J_refresh set); otherwise a failure below TR_ALPHA_MIN returns TR_ENOPROGRESS. */
static int line_search(const tr_model *m, tr_data *d, double phi0)
{
    const int k = d->k;
    double alpha = 1.0;
    int i;
    for (;;) {
        double phi;
        int status;
        if (d->nfev >= d->opt.max_nfev) {
            tr_set_message(d,
                           "function-evaluation limit (max_nfev = %d) reached at iteration %d "
                           "(scaled residual %.3g > tol %.3g); raise max_nfev",
                           d->opt.max_nfev, d->nit, d->fnorm, tr_tol(d));
            return TR_EMAXFEV;
        }
        for (i = 0; i < k; i++) d->xt[i] = d->x[i] + alpha * d->dx[i];
        status = tr_residual(m, d, d->xt, d->ft);
        if (d->stop) return d->stop;
        phi = status == TR_OK ? tru_sumsq(d->ft, k) : INFINITY;
        if (phi <= (1.0 - 2.0 * TR_ARMIJO * alpha) * phi0) return 1;
        if (!d->J_fresh) {
            d->J_refresh = 1;
            return 0;
        }
        if (isfinite(phi)) {
            /* minimiser of the quadratic through phi0, slope -2 phi0, phi(alpha) */
            double an = phi0 * alpha * alpha / (phi - phi0 + 2.0 * phi0 * alpha);
            if (!(an >= 0.1 * alpha)) an = 0.1 * alpha;
            if (an > 0.5 * alpha) an = 0.5 * alpha;
            alpha = an;
        } else {
            alpha *= 0.25;
        }
        if (alpha < TR_ALPHA_MIN) {
            if (d->fnorm < TR_ROUNDOFF_HINT)
                tr_set_message(d,
                               "no progress at iteration %d: the scaled residual stalled at "
                               "%.3g > tol %.3g, near the round-off level of this scene (large "
                               "tensions or stiffness ratios); loosen tol",
                               d->nit, d->fnorm, tr_tol(d));
            else
                tr_set_message(d,
                               "no progress at iteration %d: the line search found no "
                               "decrease of the scaled residual (%.3g) along the Newton "
                               "direction; the scene may have no equilibrium nearby (e.g. past "
                               "a buckling or slack limit), or the guess is poor",
                               d->nit, d->fnorm);
            return TR_ENOPROGRESS;
        }
    }
}

/* Take the accepted trial point: Broyden update (fd method), then, for a tendon
 * that switched between taut and slack (its Jacobian column jumps: semismooth),
 * a fresh column when the step made good progress. */
static void accept_step(const tr_model *m, tr_data *d, double phi0)
{
    const int k = d->k, off = tr_n_force(m), gend = off + m->ndisp;
    const double ratio = sqrt(tru_sumsq(d->ft, k) / (phi0 > 0.0 ? phi0 : 1.0));
    int i, j;
    if (d->jac_method == TR_JAC_FD) {
        double ss = 0.0;
        for (i = 0; i < k; i++) {
            d->dx[i] = d->xt[i] - d->x[i];
            ss += d->dx[i] * d->dx[i];
        }
        if (ss > 0.0) broyden_update(k, d->J, d->dx, ss, d->f, d->ft);
    }
    for (j = off; j < gend; j++) d->switched[j - off] = (d->x[j] > 0.0) != (d->xt[j] > 0.0);
    memcpy(d->x, d->xt, (size_t)k * sizeof(double));
    memcpy(d->f, d->ft, (size_t)k * sizeof(double));
    if (d->jac_method == TR_JAC_FD && !(ratio > TR_BROYDEN_RATIO))
        for (j = off; j < gend; j++)
            if (d->switched[j - off] &&
                tr_fd_column(m, d, d->x, d->f, j, d->J + j, (size_t)k, 0) != TR_OK)
                break; /* the remaining columns keep their Broyden update */
    d->fnorm = tru_maxnorm(d->f, k);
    d->J_fresh = 0;
    d->J_refresh = ratio > TR_BROYDEN_RATIO;
    d->nit++;
}

/* The largest Newton step (scaled unknowns): TR_MAX_STEP, or in shared mode also
 * TR_SHARED_GROW times the largest tension unknown. */
static double step_cap(const tr_model *m, const tr_data *d)
{
    double cap = TR_MAX_STEP;
    int i;
    if (!d->shared_mode) return cap;
    for (i = 0; i < m->nt; i++) {
        const int g = m->tendon[i].gamma_index;
        if (g >= 0 && TR_SHARED_GROW * fabs(d->x[tr_n_force(m) + g]) > cap)
            cap = TR_SHARED_GROW * fabs(d->x[tr_n_force(m) + g]);
    }
    return cap;
}

int tr_solve_iterate(const tr_model *m_, tr_data *d)
{
    const tr_model *m = TR_IN(m_, d);
    const int k = d->k;
    int attempt, i;
    for (attempt = 0; attempt < 3; attempt++) {
        double phi0, dmax;
        int status;
        if (!d->have_J || d->J_refresh || (d->jac_method == TR_JAC_NEWTON && !d->J_fresh)) {
            status = tr_fd_jacobian(m, d);
            if (status != TR_OK) {
                if (status != TR_EMAXFEV && !d->stop)
                    tr_set_message(d, "the residual became non-finite while forming the Jacobian");
                return status;
            }
        }
        if (tr_lu_factor(d) != 0 || tr_lu_solve(d, d->f, d->dx) != 0) {
            if (d->stop) return d->stop;
            if (!d->J_fresh) {
                d->J_refresh = 1;
                continue;
            }
            tr_set_message(d,
                           "singular Jacobian at iteration %d (scaled residual %.3g): the "
                           "unknowns are not determined by the boundary conditions (statically "
                           "indeterminate tendons, or a tendon whose tension cannot act)",
                           d->nit, d->fnorm);
            return TR_ESINGULAR;
        }
        for (i = 0; i < k; i++) d->dx[i] = -d->dx[i];
        dmax = tru_maxnorm(d->dx, k);
        if (dmax > step_cap(m, d))
            for (i = 0; i < k; i++) d->dx[i] *= step_cap(m, d) / dmax;
        phi0 = tru_sumsq(d->f, k);
        status = line_search(m, d, phi0);
        if (status < 0) return status;
        if (status == 0) continue; /* stale Jacobian rejected: retry with a fresh one */
        accept_step(m, d, phi0);
        return TR_CONTINUE;
    }
    tr_set_message(d, "no progress at iteration %d even with a fresh Jacobian", d->nit);
    return TR_ENOPROGRESS;
}

int tr_newton_run(const tr_model *m_, tr_data *d, int max_iter, int stall, double ratio)
{
    const tr_model *m = TR_IN(m_, d);
    int it = 0;
    double hist[TR_STALL_ITERS]; /* residual norms of the last TR_STALL_ITERS iterations */
    if (d->jac_method == TR_JAC_HYBRID && d->hyb) {
        const int st = tr_hybrid_run(m, d, max_iter);
        return d->stop ? d->stop : st;
    }
    for (;;) {
        int status;
        if (tr_solve_test(m, d) == TR_OK) return TR_OK;
        if (d->stop) return d->stop;
        /* creeping (tiny damped steps along a curved valley, e.g. the common-mode
         * tension of stiff tendons under twist): give up early, so that the caller's
         * continuation starts before max_iter evaluations are spent */
        if (it >= stall && d->fnorm > ratio * hist[(it - stall) % TR_STALL_ITERS]) {
            tr_set_message(d,
                           "stagnated (scaled residual %.3g > tol %.3g, down by less than "
                           "%gx in %d iterations); give a guess from a nearby solved scene",
                           d->fnorm, tr_tol(d), 1.0 / ratio, stall);
            return TR_EMAXITER;
        }
        hist[it % TR_STALL_ITERS] = d->fnorm;
        if (d->nfev >= d->opt.max_nfev) {
            tr_set_message(d,
                           "function-evaluation limit (max_nfev = %d) reached (scaled residual "
                           "%.3g > tol %.3g); raise max_nfev",
                           d->opt.max_nfev, d->fnorm, tr_tol(d));
            return TR_EMAXFEV;
        }
        if (it >= max_iter) {
            tr_set_message(d,
                           "did not converge in %d iterations (scaled residual %.3g > tol %.3g); "
                           "raise max_iter, or give a guess from a nearby solved scene",
                           max_iter, d->fnorm, tr_tol(d));
            return TR_EMAXITER;
        }
        status = tr_solve_iterate(m, d);
        it++;
        if (status < 0) return status;
    }
}

int tr_solve_lean(const tr_model *m_, tr_data *d, const double *x0, const double *jac, int max_iter)
{
    const tr_model *m = TR_IN(m_, d);
    const int k = d->k;
    double fn, fnt;
    int i, st;
    if (!TR_OWNS(m, d)) {
        tr_set_message(d, "workspace was allocated for a different model");
        return d->status = TR_EINVAL;
    }
    tr_solve_reset(m, d, d->opt.steps);
    if (jac) {
        memcpy(d->J, jac, (size_t)k * k * sizeof(double));
        d->have_J = 1;
    }
    if (m->scene_status != TR_OK || d->opt.steps <= 0 || d->opt.integrator == TR_ADAPTIVE ||
        !d->have_J) {
        tr_set_message(d, "a lean solve needs a solvable scene, fixed steps and a Jacobian");
        return d->status = TR_EINVAL;
    }
    memcpy(d->x, x0, (size_t)k * sizeof(double));
    if (tr_residual(m, d, d->x, d->f) != TR_OK)
        return d->status = d->stop ? d->stop : TR_ENONFINITE;
    fn = tru_maxnorm(d->f, k);
    while (!(fn <= tr_tol(d))) {
        double ss = 0.0;
        if (d->stop) return d->status = d->stop;
        if (d->nit >= max_iter || d->nfev >= d->opt.max_nfev) return d->status = TR_EMAXITER;
        if (tr_lu_factor(d) != 0 || tr_lu_solve(d, d->f, d->dx) != 0)
            return d->status = d->stop ? d->stop : TR_ESINGULAR;
        for (i = 0; i < k; i++) {
            d->dx[i] = -d->dx[i];
            d->xt[i] = d->x[i] + d->dx[i];
        }
        st = tr_residual(m, d, d->xt, d->ft);
        if (d->stop) return d->status = d->stop;
        fnt = st == TR_OK ? tru_maxnorm(d->ft, k) : INFINITY;
        if (!(fnt < fn)) return d->status = TR_ENOPROGRESS;
        for (i = 0; i < k; i++) ss += d->dx[i] * d->dx[i];
        if (tru_maxnorm(d->dx, k) > TR_LEAN_BROYDEN_MIN_STEP)
            broyden_update(k, d->J, d->dx, ss, d->f, d->ft);
        memcpy(d->x, d->xt, (size_t)k * sizeof(double));
        memcpy(d->f, d->ft, (size_t)k * sizeof(double));
        fn = fnt;
        d->nit++;
    }
    d->fnorm = d->residual_norm = fn;
    d->J_fresh = 0;
    tr_message_converged(d->message, TR_MSGLEN, d->nit, d->residual_norm, tr_tol(d));
    return d->status = TR_OK;
}
