/*
 * tr_dyn.c -- the dynamics in time (tr_dyn.h): BDF-alpha steps, each a boundary-value
 * problem in s solved by the shooting core with the time step's context (tr_dyn_ctx)
 * in the spatial right-hand side.
 *
 * Every time derivative is y_t = c0 y + y_h with (Till, Aloi and Rucker 2019)
 *   c0 = (3/2 + alpha) / (dt (1 + alpha)),   y_h = c1 y(i-1) + c2 y(i-2) + d1 y_t(i-1),
 *   c1 = -2 / dt,   c2 = (1/2 + alpha) / (dt (1 + alpha)),   d1 = alpha / (1 + alpha):
 * alpha = -1/2 is the trapezoidal rule (second order, no numerical damping: the energy of
 * an undamped linear motion is kept exactly), alpha = 0 BDF2 (second order, damps the
 * fast modes).  The history lives at the stage points of the fixed RK4 grid in s, the
 * same points every step.  Nothing allocates per step: the run's buffers come at its
 * start.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tendonrod.h"
#include "tr_data.h"
#include "tr_dyn.h"
#include "tr_internal.h"
#include "tru_math.h"

int tr_dyn_points(const tr_model *m, const tr_data *d)
{
    int seg, n = 0;
    for (seg = 0; seg < m->nseg; seg++) n += 4 * tr_segment_steps(m, d, seg);
    return n;
}

int tr_dyn_state_len(const tr_model *m, tr_data *d)
{
    tr_solve_reset(m, d, d->opt.steps); /* the run's grid */
    return 3 * tr_dyn_points(m, d) * TR_DH_N + 2 * d->k + 4 + m->nt;
}

int tr_dyn_nodes(const tr_model *m, tr_data *d)
{
    tr_solve_reset(m, d, d->opt.steps); /* the run's grid */
    return tr_dyn_points(m, d) / 4 + 1;
}

double tr_dyn_growth(const tr_model *m, double rhoA, double dt, double alpha)
{
    const double c0 = (1.5 + alpha) / (dt * (1.0 + alpha));
    const double k = rhoA * c0 * c0 / 4.0;
    double g = m->shoot_growth;
    int seg;
    for (seg = 0; seg < m->nseg; seg++)
        g += (m->bp[seg + 1] - m->bp[seg]) * pow(k / m->seg_rod[seg * TR_SR_NCOL + TR_SR_EI], 0.25);
    return g;
}

int tr_dyn_segments(const tr_model *m, double rhoA, double dt, double alpha)
{
    const double g = tr_dyn_growth(m, rhoA, dt, alpha), M = ceil(g / TR_DYN_SHOOT_PER);
    if (!(g > TR_DYN_SHOOT_ONE)) return 1;
    return M > TR_MAX_SHOOTING_SEGMENTS ? TR_MAX_SHOOTING_SEGMENTS : (int)M;
}

int tr_dyn_retry_segments(const tr_model *m, double rhoA, double dt, double alpha, int st)
{
    const int M2 = 2 * m->nshoot;
    if (st == TR_OK || st == TR_EINVAL || st == TR_ENOMEM || st == TR_EBUDGET ||
        st == TR_EINTERRUPTED || M2 > TR_MAX_SHOOTING_SEGMENTS)
        return 0;
    return tr_dyn_growth(m, rhoA, dt, alpha) / M2 >= TR_DYN_SHOOT_RETRY_PER ? M2 : 0;
}

static int check(const tr_model *m, const tr_data *d, const tr_dyn_spec *sp, char *msg, size_t len)
{
    if (m->planar || m->kirchhoff || m->nfric || d->opt.integrator != TR_RK4 || d->opt.steps <= 0) {
        snprintf(msg, len,
                 "the dynamics needs the spatial formulation of a Cosserat rod without channel "
                 "friction, fixed RK4 steps (planar %d, Kirchhoff %d, "
                 "frictional tendons %d, steps %d)",
                 m->planar, m->kirchhoff, m->nfric, d->opt.steps);
        return TR_EINVAL;
    }
    if (!(sp->nsteps >= 1) || !(sp->dt > 0.0) || !isfinite(sp->dt) || !(sp->alpha >= -0.5) ||
        !(sp->alpha <= 0.0) || !(sp->rhoA > 0.0) || !(sp->rhoJ[0] >= 0.0) ||
        !(sp->rhoJ[1] >= 0.0) || !(sp->rhoJ[2] >= 0.0) || !(sp->eta >= 0.0) || !(sp->drag >= 0.0) ||
        sp->max_iter < 1 || !sp->values) {
        snprintf(msg, len,
                 "dynamics: nsteps %d, dt %g, alpha %g (in [-0.5, 0]), rho A %g (> 0), eta %g, "
                 "drag %g, max_iter %d out of range",
                 sp->nsteps, sp->dt, sp->alpha, sp->rhoA, sp->eta, sp->drag, sp->max_iter);
        return TR_EINVAL;
    }
    return TR_OK;
}

/* The run's buffers, one block. */
typedef struct {
    double *X0, *X1, *X2, *Xt, *H, *wt, *xp, *x1, *xm, *J, *f0;
    double *block;
} bufs;

static int bufs_alloc(bufs *b, int npt, int k)
{
    const size_t n = (size_t)npt * TR_DH_N;
    double *q =
        (double *)calloc(5 * n + (size_t)npt + 4 * (size_t)k + (size_t)k * k, sizeof(double));
    if (!q) return -1;
    b->block = q;
    b->X0 = q, q += n;
    b->X1 = q, q += n;
    b->X2 = q, q += n;
    b->Xt = q, q += n;
    b->H = q, q += n;
    b->wt = q, q += npt;
    b->xp = q, q += k;
    b->x1 = q, q += k;
    b->xm = q, q += k;
    b->f0 = q, q += k;
    b->J = q;
    return 0;
}

/* RK4 quadrature weights of the stage points: h (1, 2, 2, 1) / 6 per step. */
static void weights(const tr_model *m, const tr_data *d, double *wt)
{
    int seg, j, p = 0;
    for (seg = 0; seg < m->nseg; seg++) {
        const int ns = tr_segment_steps(m, d, seg);
        const double h = (m->bp[seg + 1] - m->bp[seg]) / ns;
        for (j = 0; j < ns; j++, p += 4) {
            wt[p] = wt[p + 3] = h / 6.0;
            wt[p + 1] = wt[p + 2] = h / 3.0;
        }
    }
}

/* The arc lengths of the backbone nodes: the RK4 steps' starts in every segment between
 * breakpoints (steps of unequal length where the breakpoints are uneven), and L. */
static void node_s(const tr_model *m, const tr_data *d, double *s)
{
    int seg, j, p = 0;
    for (seg = 0; seg < m->nseg; seg++) {
        const int ns = tr_segment_steps(m, d, seg);
        const double h = (m->bp[seg + 1] - m->bp[seg]) / ns;
        for (j = 0; j < ns; j++) s[p++] = m->bp[seg] + j * h;
    }
    s[p] = m->bp[m->nseg];
}

/* Set the step's values (actuation, point loads, distributed load) of time row i: row 0
 * the start's, the distributed load the model's from row 1 on. */
static int set_row(const tr_model *m, tr_data *d, const tr_dyn_spec *sp, int i)
{
    char msg[TR_MSGLEN];
    const double *ld = sp->loads ? sp->loads + (size_t)i * 6 * m->nl : NULL;
    const double *dist = i == 0 && sp->dist0 ? sp->dist0 : m->dist;
    return tr_data_set_values(m, d, sp->values + (size_t)i * m->nt, ld, dist, msg, sizeof msg);
}

/* The finite-difference Jacobian at x into J (k x k row-major); f0 = residual at x. */
static int fd_jacobian(const tr_model *m, tr_data *d, const double *x, double *f0, double *J)
{
    int j, st;
    if ((st = tr_residual(m, d, x, f0)) != TR_OK) return st;
    for (j = 0; j < d->k; j++)
        if ((st = tr_fd_column(m, d, x, f0, j, J + j, (size_t)d->k, 0)) != TR_OK) return st;
    return TR_OK;
}

/* Row i of the outputs from the converged evaluation (stage values in X). */
static void output(const tr_model *m, tr_data *d, const tr_dyn_spec *sp, tr_dyn_out *o, int i,
                   const double *X, const double *wt, int npt, double *pd_prev)
{
    const tr_model *v = TR_IN(m, d);
    double ek = 0.0, ee = 0.0, ep = 0.0, pd = 0.0, *e;
    int p, j;
    tr_tip_state(m, d);
    memcpy(o->tip + 12 * (size_t)i, d->tip, 12 * sizeof(double));
    for (j = 0; j < m->nt; j++) {
        o->tension[(size_t)i * m->nt + j] = d->tension[j];
        o->slack[(size_t)i * m->nt + j] = d->slack[j];
    }
    for (p = 0; p < npt; p++) {
        const double *x = X + (size_t)p * TR_DH_N;
        ek += wt[p] * x[TR_DH_EK];
        ee += wt[p] * x[TR_DH_EE];
        pd += wt[p] * x[TR_DH_PD];
        if (v->has_dist)
            ep -= wt[p] * (v->dist[0] * x[TR_DH_P] + v->dist[1] * x[TR_DH_P + 1] +
                           v->dist[2] * x[TR_DH_P + 2]);
    }
    e = o->energy + TR_DYN_NE * (size_t)i;
    e[0] = ek;
    e[1] = ee;
    e[2] = ep;
    e[3] = i == 0 ? 0.0 : e[3 - TR_DYN_NE] + 0.5 * sp->dt * (*pd_prev + pd);
    /* the displacement-held tendons: their strain energy tau^2 rest / (2 EA) and the
     * motors' work, the trapezoidal sum of tau dq (q > 0 retracts against tau) */
    e[4] = 0.0;
    e[5] = i == 0 ? 0.0 : e[5 - TR_DYN_NE];
    for (j = 0; j < m->nt; j++) {
        const tr_tendon *t = &v->tendon[j];
        const double tau = d->tension[j];
        const size_t r = (size_t)i * m->nt + j;
        if (t->control != TR_DISPLACEMENT) continue;
        if (isfinite(t->EA)) e[4] += 0.5 * tau * tau * t->rest / (t->EA * d->ea_scale);
        if (i > 0)
            e[5] += 0.5 * (tau + o->tension[r - m->nt]) * (sp->values[r] - sp->values[r - m->nt]);
    }
    *pd_prev = pd;
    if (o->backbone) {
        const int nb = npt / 4 + 1;
        double *bb = o->backbone + (size_t)i * nb * 3;
        for (p = 0; p < npt; p += 4)
            memcpy(bb + 3 * (p / 4), X + (size_t)p * TR_DH_N, 3 * sizeof(double));
        memcpy(bb + 3 * (nb - 1), d->tip, 3 * sizeof(double));
    }
}

/* Newton with backtracking from xp and a fresh difference Jacobian at every iterate: the
 * fallback of a step the lean solve does not converge (a kink of the actuation, a tendon
 * going slack).  The last evaluation is at the converged unknowns (d->x). */
static int damped_newton(const tr_model *m, tr_data *d, const tr_dyn_spec *sp, bufs *b,
                         tr_dyn_out *o)
{
    const int k = d->k;
    double fn;
    int it, i, st;
    memcpy(d->x, b->xp, (size_t)k * sizeof(double));
    if ((st = tr_residual(m, d, d->x, d->f)) != TR_OK) return st;
    o->nfev++;
    fn = tru_maxnorm(d->f, k);
    for (it = 0; !(fn <= tr_tol(d)); it++) {
        double lam = 1.0;
        if (it >= 4 * sp->max_iter) return TR_EMAXITER;
        for (i = 0; i < k; i++)
            if ((st = tr_fd_column(m, d, d->x, d->f, i, d->J + i, (size_t)k, 0)) != TR_OK)
                return st;
        o->nfev += k;
        o->njev++;
        if (tr_lu_factor(d) != 0 || tr_lu_solve(d, d->f, d->dx) != 0)
            return d->stop ? d->stop : TR_ESINGULAR;
        for (;;) {
            double fnt = INFINITY;
            for (i = 0; i < k; i++) d->xt[i] = d->x[i] - lam * d->dx[i];
            st = tr_residual(m, d, d->xt, d->ft);
            o->nfev++;
            if (d->stop) return d->stop;
            if (st == TR_OK) fnt = tru_maxnorm(d->ft, k);
            if (fnt < (1.0 - 1e-4 * lam) * fn) {
                memcpy(d->x, d->xt, (size_t)k * sizeof(double));
                memcpy(d->f, d->ft, (size_t)k * sizeof(double));
                fn = fnt;
                break;
            }
            lam *= 0.5;
            if (lam < TR_DYN_MIN_LAMBDA) return TR_ENOPROGRESS;
        }
        o->nit++;
    }
    d->residual_norm = fn;
    d->nit = it;
    memcpy(b->J, d->J, (size_t)k * k * sizeof(double));
    return TR_OK;
}

/* A step's work budget: the options' max_work per step. */
static void step_budget(tr_data *d)
{
    d->spent = 0.0;
}

/* The caller's poll hook between steps, about every TR_POLL_INTERVAL of the run: a lean
 * solve restarts the poll's clock (tr_solve_reset), so steps shorter than the interval
 * would never reach the hook inside a solve.  1: stop (d->stop set). */
static int step_poll(tr_data *d, double *t_poll)
{
    const double now = d->poll ? tr_clock() : 0.0;
    if (!d->poll || now - *t_poll < TR_POLL_INTERVAL) return 0;
    *t_poll = now;
    if (!d->poll(d->poll_ctx)) return 0;
    d->stop = TR_EINTERRUPTED;
    return 1;
}

/* One step's Newton solve from the predictor xp: the Jacobian carried from the step before
 * (Broyden-updated there) first, a fresh difference one at xp when that fails (or there is
 * none), then Newton with backtracking. */
static int step_solve(const tr_model *m, tr_data *d, const tr_dyn_spec *sp, bufs *b, int *have_J,
                      tr_dyn_out *o)
{
    int st = TR_ENOPROGRESS, tries;
    for (tries = *have_J ? 0 : 1; tries < 2; tries++) {
        step_budget(d);
        if (tries == 1) {
            if ((st = fd_jacobian(m, d, b->xp, b->f0, b->J)) != TR_OK) return st;
            o->nfev += d->k + 1;
            o->njev++;
        }
        st = tr_solve_lean(m, d, b->xp, b->J, sp->max_iter);
        o->nit += d->nit;
        o->nfev += d->nfev;
        if (st == TR_OK) {
            memcpy(b->J, d->J, (size_t)d->k * d->k * sizeof(double)); /* Broyden-updated */
            *have_J = 1;
            return TR_OK;
        }
        if (st == TR_EBUDGET || st == TR_EINTERRUPTED) return st;
    }
    step_budget(d);
    st = damped_newton(m, d, sp, b, o);
    *have_J = st == TR_OK;
    return st;
}

int tr_dyn_run(const tr_model *m, tr_data *d, const double *x0, const tr_dyn_spec *sp,
               tr_dyn_out *o)
{
    const int k = d->k;
    const double a = sp->alpha, dt = sp->dt;
    const double c0 = (1.5 + a) / (dt * (1.0 + a)), c1 = -2.0 / dt;
    const double c2 = (0.5 + a) / (dt * (1.0 + a)), d1 = a / (1.0 + a);
    tr_dyn_ctx ctx;
    bufs b;
    int npt, i, st, have_J = 0;
    double t_poll = tr_clock();
    double pd_prev = 0.0;
    o->done = 0;
    o->nit = o->nfev = o->njev = 0;
    o->message[0] = '\0';
    if ((st = check(m, d, sp, o->message, sizeof o->message)) != TR_OK) return st;
    tr_solve_reset(m, d, d->opt.steps); /* the grid every evaluation of the run integrates */
    npt = tr_dyn_points(m, d);
    if (bufs_alloc(&b, npt, k) != 0) {
        snprintf(o->message, sizeof o->message, "dynamics: out of memory");
        return TR_ENOMEM;
    }
    memset(&ctx, 0, sizeof ctx);
    ctx.eta = sp->eta;
    ctx.rhoA = sp->rhoA;
    memcpy(ctx.rhoJ, sp->rhoJ, sizeof ctx.rhoJ);
    ctx.drag = sp->drag;
    ctx.hist = b.H;
    ctx.cur = b.X0;
    ctx.npt = npt;
    weights(m, d, b.wt);
    if (o->s) node_s(m, d, o->s);
    d->dyn = &ctx;
    tr_poll_start(d); /* the run's clock and its caller's hook; the work budget per step */
    if (sp->resume) { /* a previous run's last step: its history, unknowns, dissipation */
        const double *r = sp->resume;
        const size_t n = (size_t)npt * TR_DH_N;
        if (!(fabs(r[3 * n + 2 * k + 2] - dt) <= 1e-12 * dt)) {
            snprintf(o->message, sizeof o->message,
                     "dynamics: the state to resume is of dt = %g s, not %g s",
                     r[3 * n + 2 * k + 2], dt);
            st = TR_EINVAL;
            goto done;
        }
        memcpy(b.X1, r, n * sizeof(double));
        memcpy(b.X2, r + n, n * sizeof(double));
        memcpy(b.Xt, r + 2 * n, n * sizeof(double));
        memcpy(b.x1, r + 3 * n, (size_t)k * sizeof(double));
        memcpy(b.xm, r + 3 * n + k, (size_t)k * sizeof(double));
        pd_prev = r[3 * n + 2 * k];
        o->energy[3] = r[3 * n + 2 * k + 1];
        o->energy[5] = r[3 * n + 2 * k + 3];
        memcpy(o->tension, r + 3 * n + 2 * k + 4, (size_t)m->nt * sizeof(double));
        memcpy(d->x, b.x1, (size_t)k * sizeof(double));
        goto steps;
    }
    /* the start: the static problem (c0 = 0, no history) at x0, at rest, under the start's
     * values; its potential energy under the run's distributed load (the one the energy
     * balance of the steps holds with) */
    st = set_row(m, d, sp, 0);
    if (st == TR_OK) st = tr_residual(m, d, x0, b.f0);
    if (st == TR_OK && sp->dist0) {
        char msg[TR_MSGLEN];
        st = tr_data_set_values(m, d, NULL, NULL, m->dist, msg, sizeof msg);
    }
    if (st != TR_OK) {
        snprintf(o->message, sizeof o->message,
                 "dynamics: the initial state does not evaluate (%s)", tr_strerror(st));
        goto done;
    }
    o->residual[0] = tru_maxnorm(b.f0, k);
    o->iters[0] = 0;
    memcpy(d->x, x0, (size_t)k * sizeof(double));
    output(m, d, sp, o, 0, b.X0, b.wt, npt, &pd_prev);
    memcpy(b.X1, b.X0, (size_t)npt * TR_DH_N * sizeof(double));
    memcpy(b.X2, b.X0, (size_t)npt * TR_DH_N * sizeof(double));
    memcpy(b.x1, x0, (size_t)k * sizeof(double));
    memcpy(b.xm, x0, (size_t)k * sizeof(double));
steps:
    ctx.c0 = c0;
    for (i = 1; i <= sp->nsteps; i++) {
        const size_t n = (size_t)npt * TR_DH_N;
        size_t j;
        double *t;
        if ((st = set_row(m, d, sp, i)) != TR_OK) {
            snprintf(o->message, sizeof o->message, "dynamics: step %d (t = %g s): bad values", i,
                     i * dt);
            goto done;
        }
        for (j = 0; j < n; j++) b.H[j] = c1 * b.X1[j] + c2 * b.X2[j] + d1 * b.Xt[j];
        for (j = 0; j < (size_t)k; j++) b.xp[j] = 2.0 * b.x1[j] - b.xm[j];
        st = step_poll(d, &t_poll) ? TR_EINTERRUPTED : step_solve(m, d, sp, &b, &have_J, o);
        if (st != TR_OK) {
            snprintf(o->message, sizeof o->message,
                     "dynamics: step %d (t = %g s) failed: %s%s%.100s%s; the trajectory up to "
                     "t = %g s is kept (the step's shooting: %d segment%s, growth exponent "
                     "%.3g over the rod; more segments, another dt or a smoother actuation may "
                     "pass)",
                     i, i * dt, tr_strerror(st), d->message[0] ? " (" : "", d->message,
                     d->message[0] ? ")" : "", (i - 1) * dt, m->nshoot, m->nshoot > 1 ? "s" : "",
                     tr_dyn_growth(m, sp->rhoA, dt, a));
            goto done;
        }
        /* the last evaluation was at the solution: its stage values are the step's */
        o->residual[i] = d->residual_norm;
        o->iters[i] = d->nit;
        for (j = 0; j < n; j++) b.Xt[j] = c0 * b.X0[j] + b.H[j];
        t = b.X2, b.X2 = b.X1, b.X1 = b.X0, b.X0 = t;
        ctx.cur = b.X0;
        output(m, d, sp, o, i, b.X1, b.wt, npt, &pd_prev);
        memcpy(b.xm, b.x1, (size_t)k * sizeof(double));
        memcpy(b.x1, d->x, (size_t)k * sizeof(double));
        o->done = i;
    }
    snprintf(o->message, sizeof o->message, "%d steps of %g s converged (%d shooting segment%s)",
             sp->nsteps, dt, m->nshoot, m->nshoot > 1 ? "s" : "");
    st = TR_OK;
done:
    if (o->state && (o->done > 0 || sp->resume)) { /* the last good step, to resume from */
        const size_t n = (size_t)npt * TR_DH_N;
        double *r = o->state;
        memcpy(r, b.X1, n * sizeof(double));
        memcpy(r + n, b.X2, n * sizeof(double));
        memcpy(r + 2 * n, b.Xt, n * sizeof(double));
        memcpy(r + 3 * n, b.x1, (size_t)k * sizeof(double));
        memcpy(r + 3 * n + k, b.xm, (size_t)k * sizeof(double));
        r[3 * n + 2 * k] = pd_prev;
        r[3 * n + 2 * k + 1] = o->energy[TR_DYN_NE * (size_t)o->done + 3];
        r[3 * n + 2 * k + 2] = dt;
        r[3 * n + 2 * k + 3] = o->energy[TR_DYN_NE * (size_t)o->done + 5];
        memcpy(r + 3 * n + 2 * k + 4, o->tension + (size_t)o->done * m->nt,
               (size_t)m->nt * sizeof(double));
    }
    d->dyn = NULL;
    free(b.block);
    return st;
}
