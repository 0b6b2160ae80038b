/*
 * tr_act_run.c -- the run of an inverse actuation (tr_actuate.h): its solves at trial
 * controls, each warm from a converged state the run keeps; its linearisations, turned
 * into the derivatives of the target residual and of the tensions by the scaled
 * controls; the target's residual at a state; the target solved inside the shooting
 * system; the final solve.
 *
 * The target residual and its derivative D by the tip's [dx, dtheta] (base frame):
 *   - a planar tip angle: theta_tip - theta (the formulation's unwrapped angle);
 *   - a direction: the tip tangent's log map on the unit sphere about the target, the
 *     great-circle angle alpha = atan2(|B^T t|, t . t_target) along B^T t / |B^T t|
 *     (B an orthonormal basis of the plane normal to the target): linear in the bend of a
 *     constant-curvature arc, zero only at the target, no arccos;
 *   - a position (dx / L) and for a pose the rotation vector of R R_target^T, whose
 *     derivative by a world increment dR = [dtheta]x R is the inverse left Jacobian.
 */
#include "tr_act_run.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "tr_internal.h"
#include "tr_qp.h"
#include "tru_math.h"

/* ------------------------------------------------------------------ buffers */
int tr_act_check_spec(const tr_model *m_, tr_data *d, const tr_act_spec *sp)
{
    const tr_model *m = TR_IN(m_, d);
    const tr_act_target *tg = &sp->target;
    int j, i;
    if (!TR_SUCCEEDED(d->status) || !d->have_last) {
        tr_set_message(d, "actuate: the workspace holds no converged solve to start from");
        return TR_EINVAL;
    }
    if (sp->n < 1 || sp->n > m->nt || tg->m < 1 || tg->m > 6 ||
        (sp->kind != TR_ACT_SQUARE && sp->kind != TR_ACT_MIN_CHANGE &&
         sp->kind != TR_ACT_LEAST_SQUARES) ||
        !(sp->tol > 0.0) || sp->max_iter < 1 || !(sp->tau_scale > 0.0) || !(sp->k > 0.0) ||
        !(tg->L > 0.0) || sp->tip_row < 1 || sp->tip_row > m->nseg) {
        tr_set_message(d, "actuate: a specification out of range (n = %d, m = %d, kind = %d)",
                       sp->n, tg->m, sp->kind);
        return TR_EINVAL;
    }
    for (j = 0; j < sp->n; j++) {
        const int t = sp->idx[j];
        if (t < 0 || t >= m->nt || !(sp->scale[j] > 0.0) || !isfinite(sp->c0[j])) {
            tr_set_message(d, "actuate: control %d (tendon %d) out of range", j, t);
            return TR_EINVAL;
        }
        for (i = 0; i < j; i++)
            if (sp->idx[i] == t) {
                tr_set_message(d, "actuate: tendon %d is actuated twice", t);
                return TR_EINVAL;
            }
    }
    for (j = 0; tg->goal == TR_TARGET_POSITION && j < tg->m; j++)
        if (tg->rows[j] < 0 || tg->rows[j] > (tg->has_R ? 5 : 2)) {
            tr_set_message(d, "actuate: target row %d out of range", tg->rows[j]);
            return TR_EINVAL;
        }
    if (tg->goal != TR_TARGET_ANGLE && tg->goal != TR_TARGET_DIRECTION &&
        tg->goal != TR_TARGET_POSITION) {
        tr_set_message(d, "actuate: unknown target kind %d", tg->goal);
        return TR_EINVAL;
    }
    return TR_OK;
}

int tr_act_run_alloc(act_run *a, const tr_model *m_, tr_data *d, const tr_act_spec *sp)
{
    const tr_model *m = TR_IN(m_, d);
    const int n = sp->n, nt = m->nt, k = d->k;
    double *w;
    int i;
    memset(a, 0, sizeof *a);
    a->m = m, a->d = d, a->sp = sp;
    a->n = n, a->nt = nt, a->k = k, a->mt = sp->target.m;
    a->last = a->cur = a->best = -1;
    w = (double *)tr_data_take(d, tr_act_run_len(nt, k, n, sp->target.m) * sizeof(double));
    a->block = w;
    a->par = (tr_param *)tr_data_take(d, ((size_t)nt + 1) * sizeof(tr_param));
    if (!w || !a->par) {
        tr_act_run_free(a);
        return -1;
    }
    for (i = 0; i < ACT_POOL; i++) {
        act_state *s = a->pool + i;
        s->g = w, w += 6 + 2 * nt;
        s->x = w, w += k;
        s->xver = w, w += k;
        s->J = w, w += (size_t)k * k;
        s->valver = w, w += nt;
        s->tension = w, w += nt;
        s->slack = w, w += nt;
        s->key = w, w += n;
    }
    a->jac = w, w += (size_t)k * k;
    a->vals = w, w += nt;
    a->key = w, w += n;
    a->pose = w, w += 6 * (size_t)nt;
    a->ten = w, w += (size_t)nt * nt;
    a->sl = w, w += (size_t)nt * nt;
    a->lsq = w;
    for (i = 0; i < nt; i++) {
        a->par[i].kind = TR_PAR_VALUE;
        a->par[i].index = i;
    }
    return 0;
}

void tr_act_run_free(act_run *a)
{
    tr_data_drop(a->d, a->par);
    tr_data_drop(a->d, a->block);
    a->par = NULL;
    a->block = NULL;
}

int tr_act_lstsq(act_run *a, int rows, int cols, const double *M, const double *b, double rcond,
                 double *x)
{
    return tr_lstsq(rows, cols, M, 0, b, rcond, x, a->lsq);
}

/* ------------------------------------------------------------------ the target */
/* The rotation vector phi of R (R = exp([phi]x)), without arccos. */
static void rotvec(const double R[9], double phi[3])
{
    const double v[3] = {0.5 * (R[7] - R[5]), 0.5 * (R[2] - R[6]), 0.5 * (R[3] - R[1])};
    const double s = tru_norm3(v), c = 0.5 * (R[0] + R[4] + R[8] - 1.0), th = atan2(s, c);
    int i;
    if (s > 1e-6) {
        for (i = 0; i < 3; i++) phi[i] = v[i] * (th / s);
    } else if (c > 0.0) { /* near the identity: th = s (1 + s^2 / 6 + ...) */
        for (i = 0; i < 3; i++) phi[i] = v[i] * (1.0 + s * s / 6.0);
    } else {
        /* near a half turn: the axis from the symmetric part, its sign from v */
        double B[9], axis[3], nrm;
        int j, best = 0;
        for (i = 0; i < 3; i++)
            for (j = 0; j < 3; j++)
                B[3 * i + j] = 0.5 * (R[3 * i + j] + R[3 * j + i]) - (i == j) * c;
        for (i = 1; i < 3; i++)
            if (B[4 * i] > B[4 * best]) best = i;
        for (i = 0; i < 3; i++) axis[i] = B[3 * i + best];
        nrm = tru_norm3(axis);
        if (tru_dot3(axis, v) < 0.0) nrm = -nrm;
        for (i = 0; i < 3; i++) phi[i] = th * axis[i] / nrm;
    }
}

/* J_l^-1(phi) (3 x 3 into row stride 6 of D): d log(R) = J_l^-1 dtheta. */
static void inv_left_jacobian(const double phi[3], double *D)
{
    const double th = tru_norm3(phi);
    double K[9], KK[9], coef;
    int i, j;
    tru_skew3(K, phi);
    tru_matmul3(KK, K, K);
    coef = th < 1e-6 ? 1.0 / 12.0 : 1.0 / (th * th) - (1.0 + cos(th)) / (2.0 * th * sin(th));
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++) D[6 * i + j] = (i == j) - 0.5 * K[3 * i + j] + coef * KK[3 * i + j];
}

/* The residual s->r (m) and its derivative s->D (m x 6) at the state s. */
static void residual(const tr_act_target *tg, act_state *s)
{
    const double *R = s->tip + 3;
    const int m = tg->m;
    int i, j;
    memset(s->D, 0, sizeof s->D);
    if (tg->goal == TR_TARGET_ANGLE) {
        s->r[0] = s->tip_angle - tg->theta;
        s->D[4] = 1.0;
    } else if (tg->goal == TR_TARGET_DIRECTION) {
        const double t[3] = {R[2], R[5], R[8]};
        double Bt[2], Bdt[6], cdt[3], c, sn, ss = 0.0;
        c = tru_dot3(tg->t, t);
        tru_cross3(cdt, t, tg->t); /* d(v . t) = (t x v) . dtheta, as d t = dtheta x t */
        for (i = 0; i < m; i++) {
            Bt[i] = tru_dot3(tg->BT + 3 * i, t);
            tru_cross3(Bdt + 3 * i, t, tg->BT + 3 * i);
            ss += Bt[i] * Bt[i];
        }
        sn = sqrt(ss);
        if (sn < 1e-8 * fmax(fabs(c), 1.0)) { /* at (or opposite) the target: alpha / s -> 1 */
            const double f = c > 0.0 ? 1.0 : M_PI / fmax(sn, 1e-300);
            for (i = 0; i < m; i++) {
                s->r[i] = f * Bt[i];
                for (j = 0; j < 3; j++) s->D[6 * i + 3 + j] = f * Bdt[3 * i + j];
            }
        } else {
            const double alpha = atan2(sn, c), f = alpha / sn;
            for (j = 0; j < 3; j++) {
                double ds = 0.0, dalpha, df;
                for (i = 0; i < m; i++) ds += Bt[i] * Bdt[3 * i + j];
                ds /= sn; /* d|B^T t| by dtheta_j */
                dalpha = (c * ds - sn * cdt[j]) / (sn * sn + c * c);
                df = (dalpha * sn - alpha * ds) / (sn * sn);
                for (i = 0; i < m; i++) s->D[6 * i + 3 + j] = f * Bdt[3 * i + j] + Bt[i] * df;
            }
            for (i = 0; i < m; i++) s->r[i] = f * Bt[i];
        }
    } else {
        double r6[6], D6[36];
        memset(D6, 0, sizeof D6);
        for (i = 0; i < 3; i++) {
            r6[i] = (s->tip[i] - tg->p[i]) / tg->L;
            D6[7 * i] = 1.0 / tg->L;
            r6[3 + i] = 0.0;
        }
        if (tg->has_R) {
            double Q[9];
            for (i = 0; i < 3; i++) /* R R_target^T */
                for (j = 0; j < 3; j++)
                    Q[3 * i + j] = R[3 * i] * tg->R[3 * j] + R[3 * i + 1] * tg->R[3 * j + 1] +
                                   R[3 * i + 2] * tg->R[3 * j + 2];
            rotvec(Q, r6 + 3);
            inv_left_jacobian(r6 + 3, D6 + 21);
        }
        for (i = 0; i < m; i++) {
            s->r[i] = r6[tg->rows[i]];
            memcpy(s->D + 6 * i, D6 + 6 * tg->rows[i], 6 * sizeof(double));
        }
    }
}

/* ------------------------------------------------------------------ states */
/* A free slot: none of the last solves', not the current iterate's, not the best one's
 * (a->best), not one of the four made last (a step may still hold it); the oldest of
 * those. */
static int free_slot(act_run *a)
{
    int i, j, best = -1;
    for (i = 0; i < ACT_POOL; i++) {
        const act_state *s = a->pool + i;
        int used = i == a->cur || i == a->best || (s->born > 0 && s->born > a->made - 4);
        for (j = 0; j < a->ncache && !used; j++) used = a->cache[j] == i;
        if (!used && (best < 0 || s->born < a->pool[best].born)) best = i;
    }
    if (best < 0 && a->ncache > 0) { /* (not reached: ACT_POOL > ACT_CACHE + 6) */
        memmove(a->cache, a->cache + 1, (size_t)(a->ncache - 1) * sizeof(int));
        a->ncache--;
        return free_slot(a);
    }
    return best;
}

static int same_key(const double *x, const double *y, int n)
{
    return memcmp(x, y, (size_t)n * sizeof(double)) == 0;
}

/* The workspace's converged state into a free slot, filed under the controls a->key
 * among the last solves (the oldest of ACT_CACHE dropped first; the same controls'
 * entry replaced where it stays): its slot. */
static int keep_state(act_run *a)
{
    tr_data *d = a->d;
    const int nt = a->nt, k = a->k, s = free_slot(a);
    act_state *st = a->pool + s;
    int i;
    tr_base_state(a->m, d, st->g);
    memcpy(st->x, d->x, (size_t)k * sizeof(double));
    memcpy(st->J, d->J, (size_t)k * k * sizeof(double));
    st->have_ver = d->have_ver && d->opt.steps == 0;
    st->have_valver = d->have_val_ver;
    st->estver = d->est_ver;
    if (d->have_ver) memcpy(st->xver, d->x_ver, (size_t)k * sizeof(double));
    if (d->have_val_ver) memcpy(st->valver, d->val_ver, (size_t)nt * sizeof(double));
    st->steps = d->opt.integrator == TR_ADAPTIVE ? 0 : d->steps;
    memcpy(st->tension, d->tension, (size_t)nt * sizeof(double));
    memcpy(st->slack, d->slack, (size_t)nt * sizeof(double));
    memcpy(st->tip, d->tip, sizeof st->tip);
    st->tip_angle = d->tip_angle;
    memcpy(st->key, a->key, (size_t)a->n * sizeof(double));
    st->born = ++a->made;
    residual(&a->sp->target, st);
    if (a->sp->kind != TR_ACT_MIN_CHANGE &&
        (a->best < 0 || tr_act_rr(a, s) < tr_act_rr(a, a->best)))
        a->best = s;
    if (a->ncache >= ACT_CACHE) {
        memmove(a->cache, a->cache + 1, (ACT_CACHE - 1) * sizeof(int));
        a->ncache--;
    }
    for (i = 0; i < a->ncache; i++)
        if (same_key(a->pool[a->cache[i]].key, st->key, a->n)) break;
    if (i == a->ncache) a->ncache++;
    a->cache[i] = s;
    a->last = s;
    a->ws_ok = 1;
    return s;
}

int tr_act_run_first(act_run *a)
{
    int j;
    for (j = 0; j < a->n; j++) a->key[j] = a->sp->c0[j];
    memcpy(a->vals, a->sp->values, (size_t)a->nt * sizeof(double));
    return keep_state(a);
}

/* The model's values at controls c (tensions clipped at 0, as a scene holds them) and
 * their key: 0, or -1 (values the model refuses). */
static int set_controls(act_run *a, const double *c)
{
    const tr_act_spec *sp = a->sp;
    char msg[TR_MSGLEN];
    int j;
    memcpy(a->vals, sp->values, (size_t)a->nt * sizeof(double));
    for (j = 0; j < a->n; j++) {
        const int i = sp->idx[j];
        const double v =
            a->m->tendon[i].control == TR_DISPLACEMENT || c[j] >= 0.0 || isnan(c[j]) ? c[j] : 0.0;
        a->vals[i] = v;
        a->key[j] = v;
    }
    return tr_data_set_values(a->m, a->d, a->vals, NULL, NULL, msg, sizeof msg) == TR_OK ? 0 : -1;
}

/* The step-verification record of slot s, or NULL. */
static const tr_verified *verified(const act_run *a, int s, tr_verified *v)
{
    const act_state *st = a->pool + s;
    if (!st->have_ver || st->steps < 1) return NULL;
    v->steps = st->steps;
    v->estimate = st->estver;
    v->x = st->xver;
    v->values = st->have_valver ? st->valver : NULL;
    return v;
}

int tr_act_solve(act_run *a, const double *c, const double *state)
{
    tr_data *d = a->d;
    tr_verified v;
    const double *jac;
    int start = -1, from, status, i;
    if (a->stop) return -1;
    a->solves++;
    if (set_controls(a, c) < 0) {
        a->ws_ok = 0;
        return -1;
    }
    /* back at controls solved before (a step the iteration returns to): from that state,
     * with its own Jacobian */
    for (i = 0; i < a->ncache && !state; i++)
        if (same_key(a->pool[a->cache[i]].key, a->key, a->n)) start = a->cache[i];
    jac = start >= 0 ? a->pool[start].J : (a->have_jac ? a->jac : NULL);
    from = start >= 0 ? start : a->last;
    d->lazy = 1;
    d->polish_once = a->polish;
    if (!jac || from < 0)
        status = tr_solve_warm(a->m, d);
    else
        status =
            tr_solve_from(a->m, d, state ? state : a->pool[from].g, jac, verified(a, from, &v));
    d->lazy = 0;
    d->polish_once = 0;
    if (status == TR_EINTERRUPTED) a->stop = status;
    if (!TR_SUCCEEDED(status)) {
        a->ws_ok = 0;
        return -1;
    }
    return keep_state(a);
}

double tr_act_rr(const act_run *a, int s)
{
    double v = 0.0;
    int i;
    for (i = 0; i < a->mt; i++) v += a->pool[s].r[i] * a->pool[s].r[i];
    return v;
}

void tr_act_psi(const act_run *a, int s, double *psi)
{
    int i;
    for (i = 0; i < a->nt; i++) psi[i] = a->pool[s].tension[i] - a->sp->k * a->pool[s].slack[i];
}

/* ------------------------------------------------------------------ linearisation */
int tr_act_linearize(act_run *a, int s, const double *side, double *A, double *T, int *sw)
{
    const tr_act_spec *sp = a->sp;
    const act_state *st = a->pool + s;
    const int n = a->n, nt = a->nt, mt = a->mt, here = a->ws_ok && a->last == s;
    tr_data *d = a->d;
    int i, j, c, status, any = 0;
    a->jacobians++;
    if (!here) {
        /* the state set without solving */
        status = tr_state_from(a->m, d, st->x, st->steps);
        a->ws_ok = 0;
        if (status != TR_OK) return status;
    }
    for (i = 0; i < nt; i++) sw[i] = (int)side[i];
    status = tr_linearize(a->m, d, a->par, nt, &sp->tip_row, 1, a->pose, a->ten, a->sl, sw,
                          TR_DIFF_FORWARD);
    if (status != TR_OK) {
        if (status == TR_EINTERRUPTED) a->stop = status;
        return status;
    }
    /* its shooting Jacobian starts the next solves (fresher than the solver's own),
     * unless a tendon sits at its switch: the map is kinked there, and the side taken
     * may not be the one those solves land on */
    for (i = 0; i < nt; i++) any |= sw[i] != 0;
    a->have_jac = here && !any;
    if (a->have_jac) memcpy(a->jac, d->J, (size_t)a->k * a->k * sizeof(double));
    for (j = 0; j < n; j++) {
        const int p = sp->idx[j];
        for (i = 0; i < mt; i++) {
            double v = 0.0;
            for (c = 0; c < 6; c++) v += st->D[6 * i + c] * a->pose[6 * p + c];
            A[i * n + j] = v * sp->scale[j];
        }
        /* the signed tension psi = tau - k slack: continuous and increasing through the
         * switch, so a slack tendon's rates are not lost */
        for (i = 0; i < nt; i++)
            T[i * n + j] = (a->ten[p * nt + i] - sp->k * a->sl[p * nt + i]) * sp->scale[j];
    }
    return TR_OK;
}

/* ------------------------------------------------------------------ augmented, final */
int tr_act_augmented(act_run *a, double *c)
{
    const tr_act_spec *sp = a->sp;
    const tr_act_target *tg = &sp->target;
    tr_data *d = a->d;
    char msg[TR_MSGLEN];
    const double *vals = tg->goal == TR_TARGET_ANGLE       ? &tg->theta
                         : tg->goal == TR_TARGET_DIRECTION ? tg->t
                                                           : tg->p;
    double q[6];
    int j, status, ok;
    if (tg->has_R || a->n != tg->m || a->n > 6 ||
        tr_data_set_target(a->m, d, tg->goal, vals, sp->idx, a->n, msg, sizeof msg) != TR_OK)
        return -1;
    a->solves++;
    d->lazy = 1;
    status = tr_solve_warm(a->m, d);
    d->lazy = 0;
    tr_data_set_target(a->m, d, TR_TARGET_NONE, NULL, NULL, 0, msg, sizeof msg);
    a->ws_ok = 0;
    if (status == TR_EINTERRUPTED) a->stop = status;
    ok = TR_SUCCEEDED(status);
    for (j = 0; j < a->n && ok; j++) {
        q[j] = d->displacement[sp->idx[j]];
        ok = isfinite(q[j]) && d->tension[sp->idx[j]] > 0.0;
    }
    if (!ok) return -1;
    j = tr_act_solve(a, q, NULL);
    if (j >= 0) memcpy(c, q, (size_t)a->n * sizeof(double));
    return j;
}

int tr_act_final(act_run *a, int s, const double *c, int judge, double *r)
{
    tr_data *d = a->d;
    act_state here;
    tr_verified v;
    const int accept = d->opt.accept_unstable;
    int status;
    a->solves++;
    if (set_controls(a, c) < 0) return TR_EINVAL;
    d->lazy = 1;
    if (judge) d->opt.accept_unstable = 0;
    status = tr_solve_from(a->m, d, a->pool[s].g, a->pool[s].J, verified(a, s, &v));
    d->opt.accept_unstable = accept;
    d->lazy = 0;
    if (status == TR_EINTERRUPTED) a->stop = status;
    memcpy(r, a->pool[s].r, (size_t)a->mt * sizeof(double));
    if (TR_SUCCEEDED(status)) {
        memcpy(here.tip, d->tip, sizeof here.tip);
        here.tip_angle = d->tip_angle;
        residual(&a->sp->target, &here);
        memcpy(r, here.r, (size_t)a->mt * sizeof(double));
    }
    return status;
}
