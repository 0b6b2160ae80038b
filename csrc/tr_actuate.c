/*
 * tr_actuate.c -- the outer iteration of an inverse actuation (tr_actuate.h):
 * trust-region steps on the linearisation of the current equilibrium (Levenberg-Marquardt
 * for square and least-squares targets, a composite-step sequential quadratic program for
 * the least change), every accepted iterate a converged solve (tr_act_run.c).
 *
 * Units: controls in their scales (u = (c - c0) / scale), residuals dimensionless,
 * tension floors on the signed tension psi = tau - k slack [N], divided by tau_scale in the
 * step's rows.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "tr_act_iter.h"
#include "tr_act_run.h"
#include "tr_internal.h"
#include "tr_qp.h"
#include "tru_math.h"

static double merit(const act_iter *it, const double *c, const double *r, const double *psi,
                    const double *floor)
{
    const tr_act_spec *sp = it->sp;
    double viol = 0.0, q = 0.0, ra = 0.0;
    int i;
    for (i = 0; i < it->nt; i++)
        if (isfinite(floor[i])) viol += fmax(floor[i] - psi[i], 0.0);
    for (i = 0; i < it->n; i++)
        q += ((c[i] - sp->c0[i]) / sp->scale[i]) * ((c[i] - sp->c0[i]) / sp->scale[i]);
    for (i = 0; i < it->mt; i++) ra += fabs(r[i]);
    return 0.5 * q + it->nu * (ra + viol / sp->tau_scale);
}

/* The Lagrangian's gradient g (n, scaled) at c with the last multipliers. */
static void grad(const act_iter *it, const double *c, const int *rows, int nr, double *g)
{
    const tr_act_spec *sp = it->sp;
    const int n = it->n;
    int i, j;
    for (j = 0; j < n; j++) {
        double v = (c[j] - sp->c0[j]) / sp->scale[j];
        for (i = 0; i < it->mt; i++) v -= it->A[i * n + j] * it->lam[i];
        for (i = 0; i < nr; i++) v -= it->T[rows[i] * n + j] / sp->tau_scale * it->mus[rows[i]];
        g[j] = v;
    }
}

/* Rows (it->G, it->h from row `at`) of the trust region |u_j| <= delta, of tension
 * controls >= 0 and, for a slack displacement control linearised on its slack side, of
 * pulls no longer than its slack (beyond it the tendon acts, which that side cannot
 * see): the row count after them, or -1 (a linearisation failed). */
static int box(act_iter *it, int at, double delta)
{
    const tr_act_spec *sp = it->sp;
    const int n = it->n;
    int j, r;
    if (!it->rows_ok) { /* the rows but the region's size: fixed at a state */
        if (tr_act_linearisation(it) < 0) return -1;
        memset(it->Gfix, 0, (size_t)(3 * n) * n * sizeof(double));
        r = 0;
        for (j = 0; j < n; j++) it->Gfix[(r + j) * n + j] = 1.0;
        r += n;
        for (j = 0; j < n; j++) it->Gfix[(r + j) * n + j] = -1.0;
        r += n;
        for (j = 0; j < n; j++)
            if (it->a->m->tendon[sp->idx[j]].control != TR_DISPLACEMENT) {
                it->Gfix[r * n + j] = 1.0;
                it->hfix[r - 2 * n] = -(it->c[j] / sp->scale[j]);
                r++;
            }
        for (j = 0; j < n; j++) {
            const int i = sp->idx[j];
            const double sl = tr_act_cur(it)->slack[i];
            if (it->disp[i] && sl > 0.0 && it->sw[i] <= 0) {
                it->Gfix[r * n + j] = -1.0;
                it->hfix[r - 2 * n] = -sl / sp->scale[j];
                r++;
            }
        }
        it->nfix = r;
        it->rows_ok = 1;
    }
    memcpy(it->G + (size_t)at * n, it->Gfix, (size_t)it->nfix * n * sizeof(double));
    for (j = 0; j < 2 * n; j++) it->h[at + j] = -delta;
    memcpy(it->h + at + 2 * n, it->hfix, (size_t)(it->nfix - 2 * n) * sizeof(double));
    return at + it->nfix;
}

/* The QP of tr_qp.h on the iteration's buffers: 0, or -1 (it->err set). */
static int qp(act_iter *it, const double *H, const double *g, int me, const double *A, int mi,
              const double *x0, double *u, double *lam)
{
    const int st =
        tr_qp(it->n, H, g, me, A, mi, it->G, it->h, x0, 200, u, lam, it->mu, it->active, it->qpw);
    if (st < 0) {
        it->err = st;
        return -1;
    }
    return 0;
}

/* |r + A u|^2 */
static double predicted(const act_iter *it, const double *r, const double *u)
{
    double s = 0.0;
    int i;
    for (i = 0; i < it->mt; i++) {
        const double v = r[i] + tr_act_dot(it->A + i * it->n, u, it->n);
        s += v * v;
    }
    return s;
}

/* Move to the solved state s at controls cn; with rows (the tension floors of the least
 * change), the BFGS update.  0, or -1 (a linearisation failed). */
static int accepted(act_iter *it, const double *cn, int s, const int *rows, int nr)
{
    const int n = it->n;
    int i, same = 1;
    if (rows) {
        /* cn kept: the new state's linearisation may take up slack, moving it->c on */
        memcpy(it->ca, cn, (size_t)n * sizeof(double));
        grad(it, it->c, rows, nr, it->gold);
        for (i = 0; i < n; i++) it->s[i] = (cn[i] - it->c[i]) / it->sp->scale[i];
        for (i = 0; i < it->nt; i++)
            same &= (tr_act_cur(it)->tension[i] > 0.0) == (it->a->pool[s].tension[i] > 0.0);
        tr_act_set_state(it, cn, s);
        if (same) {
            if (tr_act_linearisation(it) < 0) return -1;
            grad(it, it->ca, rows, nr, it->gnew);
            for (i = 0; i < n; i++) it->y[i] = it->gnew[i] - it->gold[i];
            tr_bfgs_update(it->n, it->H, it->s, it->y, it->Hs);
        } else {
            /* a tendon crossed its taut/slack switch: the Lagrangian's gradient jumps there,
             * so the change of gradient measures no curvature; start afresh */
            memset(it->H, 0, (size_t)n * n * sizeof(double));
            for (i = 0; i < n; i++) it->H[i * n + i] = 1.0;
        }
    } else {
        tr_act_set_state(it, cn, s);
    }
    it->rejected = 0;
    return 0;
}

/* 1: the run has solved a state whose target residual is below the current one's by more
 * than the tolerance (square and least squares; the solves resolve nothing finer). */
static int better_known(const act_iter *it)
{
    const act_run *a = it->a;
    return a->best >= 0 && a->best != a->cur &&
           sqrt(tr_act_rr(a, a->best)) < sqrt(tr_act_rr(a, a->cur)) - it->sp->tol;
}

/* Back to the best state solved (its controls, the key it was solved at), the trust region
 * at half the distance to it: the step from there was the one the solves did not bear out. */
static void to_best(act_iter *it)
{
    const act_state *b = it->a->pool + it->a->best;
    double dmax = 0.0;
    int j;
    for (j = 0; j < it->n; j++) dmax = fmax(dmax, fabs(b->key[j] - it->c[j]) / it->sp->scale[j]);
    tr_act_set_state(it, b->key, it->a->best);
    it->delta = fmax(dmax / 2.0, 1e-6);
    it->rejected = 0;
}

/* A step the solved states do not bear out: the trust region shrinks below it.  After
 * TR_ACT_MAX_REJECTED in a row the region has collapsed: the iteration goes on from the
 * best state it solved where that is better than the current one (a trial refused by the
 * fidelity test may have reduced the residual), else it stops. */
static int refused(act_iter *it, const double *u)
{
    it->delta = tru_maxnorm(u, it->n) / 4.0;
    it->rejected++;
    if (it->rejected < TR_ACT_MAX_REJECTED) return TR_ACT_REJECTED;
    if (it->lsq && better_known(it)) {
        to_best(it);
        return TR_ACT_REJECTED;
    }
    return TR_ACT_STUCK;
}

/* An accepted step whose target residual fell fast (to 1e-2 of the last one or less,
 * Newton's quadratic regime) but not below tol, corrected by the same linearisation: the
 * least-norm change that removes that residual and keeps the tensions of rows keep (nk)
 * where the step put them, solved.  Its residual is the step's times the relative change
 * of the linearisation over the step, so one correction usually meets tol where another
 * iteration (a linearisation) would be needed.  The corrected state where it reduces the
 * residual (cn updated), else the step's. */
static int chord(act_iter *it, double *cn, int s, double rnorm, const int *keep, int nk)
{
    const tr_act_spec *sp = it->sp;
    const int n = it->n, mt = it->mt;
    const double rmax = tru_maxnorm(it->a->pool[s].r, mt);
    int i, j, s2;
    if (!(sp->tol < rmax && rmax <= 1e-2 * rnorm)) return s;
    memcpy(it->M, it->A, (size_t)mt * n * sizeof(double));
    for (i = 0; i < nk; i++)
        for (j = 0; j < n; j++) it->M[(mt + i) * n + j] = it->T[keep[i] * n + j] / sp->tau_scale;
    for (i = 0; i < mt; i++) it->rhs[i] = -it->a->pool[s].r[i];
    for (i = 0; i < nk; i++) it->rhs[mt + i] = 0.0;
    if (tr_act_lstsq(it->a, mt + nk, n, it->M, it->rhs, 1e-12, it->dd) < 0) return s;
    for (j = 0; j < n; j++) it->c2[j] = cn[j] + it->dd[j] * sp->scale[j];
    s2 = tr_act_solve(it->a, it->c2, NULL);
    if (s2 < 0 || !(tru_maxnorm(it->a->pool[s2].r, mt) < rmax)) {
        tr_act_solve(it->a, cn, NULL); /* the workspace's warm state back at cn */
        return s;
    }
    memcpy(cn, it->c2, (size_t)n * sizeof(double));
    return s2;
}

/* One trust-region step of the least change (a normal step toward the target, then the
 * least change keeping that progress; Byrd and Omojokun's composite step). */
static int sqp(act_iter *it)
{
    const tr_act_spec *sp = it->sp;
    const int n = it->n, mt = it->mt, nt = it->nt;
    const double *r, *c;
    double rnorm, rr, phi, viol = 0.0, mmax = 0.0;
    int i, j, nf = 0, nb, nk = 0, s, s2;
    if (tr_act_linearisation(it) < 0) return ACT_ERROR; /* first: it may move the state */
    r = tr_act_cur(it)->r, c = it->c;
    if (tr_act_floors(it, it->floor) < 0) return ACT_ERROR;
    for (i = 0; i < nt; i++)
        if (isfinite(it->floor[i])) it->rows[nf++] = i;
    tr_act_psi(it->a, it->a->cur, it->psi);
    /* the normal step toward the target within 0.8 of the trust region and the floors
     * (least squares on the linearised residual): the part of the target a step of this
     * size can reach */
    for (i = 0; i < nf; i++) {
        for (j = 0; j < n; j++) it->G[i * n + j] = it->T[it->rows[i] * n + j] / sp->tau_scale;
        it->h[i] = (it->floor[it->rows[i]] - it->psi[it->rows[i]]) / sp->tau_scale;
    }
    if ((nb = box(it, nf, 0.8 * it->delta)) < 0) return ACT_ERROR;
    tr_gauss_newton(it->n, it->mt, it->A, r, it->QH, it->qg);
    memset(it->g0, 0, (size_t)n * sizeof(double));
    if (qp(it, it->QH, it->qg, 0, it->A, nb, it->g0, it->v, it->lam) < 0) return ACT_ERROR;
    rnorm = tru_maxnorm(r, mt);
    rr = tr_act_dot(r, r, mt);
    if (rnorm > sp->tol && !(rr - predicted(it, r, it->v) > 1e-28 * rr))
        return TR_ACT_UNREACHABLE; /* no step within the tensions brings the target nearer */
    if ((nb = box(it, nf, it->delta)) < 0) return ACT_ERROR;
    for (j = 0; j < n; j++) it->u0[j] = (c[j] - sp->c0[j]) / sp->scale[j];
    if (qp(it, it->H, it->u0, mt, it->A, nb, it->v, it->u, it->lam) < 0) return ACT_ERROR;
    it->have_lam = 1;
    memset(it->mus, 0, (size_t)nt * sizeof(double));
    for (i = 0; i < nf; i++) it->mus[it->rows[i]] = it->mu[i];
    for (i = 0; i < mt; i++) mmax = fmax(mmax, fabs(it->lam[i]));
    for (i = 0; i < nt; i++) mmax = fmax(mmax, fabs(it->mus[i]));
    it->nu = fmax(it->nu, 2.0 * mmax + 1e-3);
    for (i = 0; i < nf; i++)
        viol = fmax(viol, fmax(it->floor[it->rows[i]] - it->psi[it->rows[i]], 0.0));
    viol /= sp->tau_scale;
    /* stay: the step and the stationarity residual H u of the linearised problem's
     * optimality conditions both below TR_ACT_KKT_TOL (scaled units), a KKT point */
    for (i = 0; i < n; i++) it->Hs[i] = tr_act_dot(it->H + i * n, it->u, n);
    if (rnorm <= sp->tol && viol <= 1e-9 &&
        fmax(tru_maxnorm(it->u, n), tru_maxnorm(it->Hs, n)) <= TR_ACT_KKT_TOL) {
        it->optimal = 1;
        return TR_ACT_DONE;
    }
    phi = merit(it, c, r, it->psi, it->floor);
    for (j = 0; j < n; j++) it->cn[j] = c[j] + it->u[j] * sp->scale[j];
    s = tr_act_solve(it->a, it->cn, NULL);
    if (s >= 0) {
        tr_act_psi(it->a, s, it->psin);
        if (!(merit(it, it->cn, it->a->pool[s].r, it->psin, it->floor) < phi)) {
            /* a second-order correction: the new target residual removed by the least-norm
             * step of the same linearisation (the target's curvature would otherwise make
             * the merit refuse steps near the solution) */
            for (i = 0; i < mt; i++) it->rhs[i] = -it->a->pool[s].r[i];
            s2 = -1;
            if (tr_act_lstsq(it->a, mt, n, it->A, it->rhs, 1e-12, it->dd) == 0) {
                for (j = 0; j < n; j++) it->c2[j] = it->cn[j] + it->dd[j] * sp->scale[j];
                s2 = tr_act_solve(it->a, it->c2, NULL);
            }
            if (s2 >= 0) tr_act_psi(it->a, s2, it->psin);
            if (s2 >= 0 && merit(it, it->c2, it->a->pool[s2].r, it->psin, it->floor) < phi) {
                for (j = 0; j < n; j++) it->u[j] += it->dd[j];
                memcpy(it->cn, it->c2, (size_t)n * sizeof(double));
                s = s2;
            } else {
                s = -1;
            }
        }
    }
    if (s < 0) return refused(it, it->u);
    if (tru_maxnorm(it->u, n) >= 0.9 * it->delta && tru_maxnorm(it->a->pool[s].r, mt) <= rnorm)
        it->delta *= 2.0;
    for (i = 0; i < nf; i++) /* the tension floors the step holds */
        if (it->mus[it->rows[i]] > 0.0) it->keep[nk++] = it->rows[i];
    s = chord(it, it->cn, s, rnorm, it->keep, nk);
    if (accepted(it, it->cn, s, it->rows, nf) < 0) return ACT_ERROR;
    return TR_ACT_MOVED;
}

/* One trust-region step on |r|^2 (square and least squares). */
static int lm(act_iter *it)
{
    const tr_act_spec *sp = it->sp;
    const int n = it->n, mt = it->mt;
    const double *r;
    double rr, pred, rho, umax, e2, au2;
    int i, j, l, nb, nheld = 0, nflip = 0, s;
    if (tru_maxnorm(tr_act_cur(it)->r, mt) <= sp->tol) return TR_ACT_DONE;
    if (tr_act_linearisation(it) < 0) return ACT_ERROR; /* first: it may take up slack */
    r = tr_act_cur(it)->r;
    tr_gauss_newton(it->n, it->mt, it->A, r, it->QH, it->qg);
    if ((nb = box(it, 0, it->delta)) < 0) return ACT_ERROR;
    /* a displacement control at its switch (taut side, no tension to speak of): its
     * linearisation holds for pulling only (paid out, it goes slack and moves nothing) */
    for (j = 0; j < n; j++) {
        const int i = sp->idx[j];
        if (it->disp[i] && it->sw[i] > 0 && tr_act_cur(it)->tension[i] <= 1e-9 * sp->tau_scale) {
            memset(it->G + (size_t)(nb + nheld) * n, 0, (size_t)n * sizeof(double));
            it->G[(nb + nheld) * n + j] = 1.0;
            it->h[nb + nheld] = 0.0;
            it->keep[nheld++] = j;
        }
    }
    memset(it->g0, 0, (size_t)n * sizeof(double));
    if (qp(it, it->QH, it->qg, 0, it->A, nb + nheld, it->g0, it->u, it->lam) < 0) return ACT_ERROR;
    /* a held tendon that the step would slacken (its predicted tension falls, through the
     * other controls) is on its slack side there, whose derivatives are not the taut
     * side's: the step again from the linearisation with that side (once per state).  The
     * fall counts where it takes the tension below zero by more than 1e-6 of its terms'
     * sizes, the round-off of the forward-difference rates; a bound on the tension scale
     * instead would let the short steps near a target slacken a held tendon unseen, every
     * one of them refused */
    for (j = 0; j < nheld; j++) {
        const int i = sp->idx[it->keep[j]];
        double size = 0.0;
        for (l = 0; l < n; l++) size += fabs(it->T[i * n + l] * it->u[l]);
        if (tr_act_cur(it)->tension[i] + tr_act_dot(it->T + i * n, it->u, n) < -1e-6 * size)
            it->slack_side[nflip++] = i;
    }
    if (nflip && !it->nslack_side) {
        it->nslack_side = nflip;
        it->lin = it->rows_ok = 0;
        return lm(it);
    }
    /* (the rows after the region's 2n: bounds, held controls) */
    it->gcos = tr_lsq_cosine(n, mt, it->A, r, nb + nheld - 2 * n, it->G + 2 * n * n, it->h + 2 * n);
    it->gcos_at = it->a->cur;
    rr = tr_act_dot(r, r, mt);
    pred = rr - predicted(it, r, it->u);
    umax = tru_maxnorm(it->u, n);
    if (!(pred > 1e-28 * rr) || umax <= 1e-13) {
        if (it->lsq && better_known(it)) { /* (not a minimum: a better state is known) */
            to_best(it);
            return TR_ACT_REJECTED;
        }
        return TR_ACT_STUCK; /* no descent left: a (bounded) least-squares point */
    }
    for (j = 0; j < n; j++) it->cn[j] = it->c[j] + it->u[j] * sp->scale[j];
    s = tr_act_solve(it->a, it->cn, NULL);
    if (s < 0) return refused(it, it->u);
    /* the fidelity of the linearisation over the step: e = r_new - (r + A u) against A u */
    e2 = au2 = 0.0;
    for (i = 0; i < mt; i++) {
        const double au = tr_act_dot(it->A + i * n, it->u, n);
        const double e = it->a->pool[s].r[i] - r[i] - au;
        e2 += e * e;
        au2 += au * au;
    }
    rho = (rr - tr_act_rr(it->a, s)) / pred;
    /* (least squares: a square target's Newton steps meet its root where the residual
     * falls, so that test alone keeps them) */
    if (sp->kind != TR_ACT_LEAST_SQUARES) e2 = 0.0;
    if (tru_maxnorm(it->a->pool[s].r, mt) > sp->tol &&
        (rho <= 1e-4 || e2 > TR_ACT_FIDELITY * TR_ACT_FIDELITY * au2))
        return refused(it, it->u);
    if (rho > 0.75 && umax >= 0.9 * it->delta &&
        4.0 * e2 <= TR_ACT_FIDELITY * TR_ACT_FIDELITY * au2)
        it->delta *= 2.0;
    else if (rho < 0.25)
        it->delta = umax / 2.0;
    if (accepted(it, it->cn, s, NULL, 0) < 0) return ACT_ERROR;
    return TR_ACT_MOVED;
}

/* Minimum change: a displacement control held at its taut/slack switch above its scene
 * value is paid out to that value when the tendon stays slack there (a slack tendon moves
 * nothing, so the target stays met and the change only shrinks).  0, or -1. */
static int release(act_iter *it)
{
    const tr_act_spec *sp = it->sp;
    const double tiny = 1e-9 * sp->tau_scale;
    int j, s, ok;
    if (tr_act_linearisation(it) < 0) return -1;
    memcpy(it->cn, it->c, (size_t)it->n * sizeof(double));
    for (j = 0; j < it->n; j++) {
        const int i = sp->idx[j];
        const double ten = tr_act_cur(it)->tension[i];
        const int at_floor = it->have_lam && it->mus[i] > 0.0;
        const int at_switch = it->sw[i] > 0 || ten <= tiny;
        if (it->disp[i] && at_switch && (at_floor || ten <= 0.0) && it->cn[j] > sp->c0[j])
            it->cn[j] = sp->c0[j];
    }
    if (tr_act_equal(it->cn, it->c, it->n)) return 0;
    s = tr_act_solve(it->a, it->cn, tr_act_slack_state(it, it->cn));
    ok = s >= 0 && tru_maxnorm(it->a->pool[s].r, it->mt) <= sp->tol;
    for (j = 0; j < it->n && ok; j++)
        if (it->cn[j] != it->c[j]) ok = it->a->pool[s].tension[sp->idx[j]] == 0.0;
    if (ok) {
        tr_act_set_state(it, it->cn, s);
    } else { /* back to the verified point (and the workspace's warm state at it) */
        s = tr_act_solve(it->a, it->c, NULL);
        if (s >= 0) tr_act_set_state(it, it->c, s);
    }
    return 0;
}

/* ------------------------------------------------------------------ the verdict */
/* res->success, res->optimal, res->optimality and res->why of a run that ended at the
 * state a->cur (back: moved there, the best state solved, from a worse one):
 *   - square: the target reached (max |r| <= tol);
 *   - minimum change: reached, and its KKT point verified (it->optimal);
 *   - least squares: reached, or a least-squares point: the first-order test
 *     (TR_ACT_GTOL) holds at the state returned and the run solved no state better than
 *     it by more than tol (a run that ended worse is moved back and is no success);
 * and in every kind the final solve succeeded (res->status; judged on request). */
static void verdict(const act_iter *it, tr_act_result *res, int back)
{
    const tr_act_spec *sp = it->sp;
    const int reached = tru_maxnorm(res->r, it->mt) <= sp->tol;
    const int here = it->gcos_at == it->a->cur && !back;
    int ok;
    res->optimality = it->lsq && here ? it->gcos : NAN;
    if (sp->kind == TR_ACT_MIN_CHANGE) {
        ok = reached && it->optimal;
    } else if (sp->kind == TR_ACT_SQUARE) {
        res->optimal = reached;
        ok = reached;
    } else {
        res->optimal = reached || (here && it->gcos <= TR_ACT_GTOL);
        ok = res->optimal;
        if (!ok && !res->why[0]) {
            if (back)
                snprintf(res->why, sizeof res->why,
                         "the run ended worse than a state it had solved, which is returned");
            else if (here)
                snprintf(res->why, sizeof res->why,
                         "%s: the residual's cosine to the linearisation is %.2g > %.2g",
                         res->outcome == TR_ACT_MAX_ITER ? "out of iterations"
                                                         : "no least-squares point",
                         it->gcos, TR_ACT_GTOL);
            else
                snprintf(res->why, sizeof res->why, "out of iterations");
        }
    }
    res->success = ok && TR_SUCCEEDED(res->status);
}

/* ------------------------------------------------------------------ the run */
int tr_actuate(const tr_model *m_, tr_data *d, const tr_act_spec *sp, tr_act_result *res)
{
    const tr_model *m = TR_IN(m_, d);
    const int n = sp->n;
    act_run run, *a = &run;
    act_iter it;
    int s, j, out = TR_ACT_MOVED, status, i, nit = 0, back = 0;
    memset(res->why, 0, sizeof res->why);
    if ((status = tr_act_check_spec(m, d, sp)) != TR_OK) return status;
    if (tr_act_run_alloc(a, m, d, sp) < 0) {
        tr_set_message(d, "actuate: out of memory");
        return TR_ENOMEM;
    }
    if (tr_act_iter_alloc(&it, a, sp) < 0) {
        tr_act_run_free(a);
        return TR_ENOMEM;
    }
    s = tr_act_run_first(a);
    memcpy(it.c, sp->c0, (size_t)n * sizeof(double));
    res->augmented = 0;
    if (sp->augmented && tru_maxnorm(a->pool[s].r, it.mt) > sp->tol) {
        /* the target inside the shooting system first; the iteration polishes or takes over */
        const int s2 = tr_act_augmented(a, it.cn);
        if (s2 >= 0) {
            s = s2;
            memcpy(it.c, it.cn, (size_t)n * sizeof(double));
            res->augmented = 1;
        }
    }
    /* slack displacement controls drawn to their switch (q + slack, a hair past it), where
     * pulling them acts (the least change pays those it does not need out again) */
    memcpy(it.cn, it.c, (size_t)n * sizeof(double));
    for (j = 0; j < n; j++) {
        const int t = sp->idx[j];
        if (it.disp[t] && a->pool[s].slack[t] > 0.0)
            it.cn[j] += a->pool[s].slack[t] + 1e-12 * sp->scale[j];
    }
    if (!tr_act_equal(it.cn, it.c, n)) {
        const int s2 = tr_act_solve(a, it.cn, NULL);
        if (s2 >= 0) {
            s = s2;
            memcpy(it.c, it.cn, (size_t)n * sizeof(double));
        } else {
            const int s3 = tr_act_solve(a, it.c, NULL); /* the workspace's warm state back at c */
            if (s3 >= 0) s = s3;
        }
    }
    tr_act_set_state(&it, it.c, s);
    while (nit < sp->max_iter && !a->stop) {
        nit++;
        out = sp->kind == TR_ACT_MIN_CHANGE ? sqp(&it) : lm(&it);
        if (out == TR_ACT_UNREACHABLE)
            snprintf(res->why, sizeof res->why, "the target lies beyond what the tensions allow");
        if (out == TR_ACT_UNREACHABLE || out == TR_ACT_DONE || out == TR_ACT_STUCK ||
            out == ACT_ERROR)
            break;
    }
    if (out == TR_ACT_DONE && sp->kind == TR_ACT_MIN_CHANGE && release(&it) < 0) out = ACT_ERROR;
    if (out != ACT_ERROR && !a->stop && it.lsq && better_known(&it)) {
        /* never worse than a state the run solved (or its start): the best one returned */
        tr_act_set_state(&it, a->pool[a->best].key, a->best);
        back = 1;
    }
    if (out != ACT_ERROR && !a->stop && tr_act_floors(&it, res->floors) < 0) out = ACT_ERROR;
    status = TR_OK;
    if (a->stop) {
        status = a->stop;
    } else if (out == ACT_ERROR) {
        status = it.err;
        if (!d->message[0] || status == TR_ESINGULAR)
            tr_set_message(d, "actuate: %s",
                           status == TR_ESINGULAR ? "a step's quadratic program is singular"
                                                  : tr_strerror(status));
    } else {
        res->outcome = out == TR_ACT_MOVED || out == TR_ACT_REJECTED ? TR_ACT_MAX_ITER : out;
        res->optimal = it.optimal;
        res->iterations = nit;
        res->have_lam = it.have_lam;
        memcpy(res->lam, it.lam, sizeof res->lam);
        for (i = 0; i < a->nt; i++) res->mus[i] = it.have_lam ? it.mus[i] : 0.0;
        memcpy(res->c, it.c, (size_t)n * sizeof(double));
        res->status = tr_act_final(a, a->cur, it.c, sp->judge, res->r);
        if (a->stop) status = a->stop;
        verdict(&it, res, back);
        res->solves = a->solves;
        res->jacobians = a->jacobians;
    }
    tr_act_iter_free(&it);
    tr_act_run_free(a);
    return status;
}
