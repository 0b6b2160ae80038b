/*
 * tr_path.c -- pseudo-arclength continuation of an equilibrium branch in one parameter.
 *
 * The path runs in X = (x, lambda): the scaled shooting unknowns x (k) and lambda =
 * (p - p0) / (p1 - p0).  Each step predicts along the unit tangent t of the last point,
 * X_a + ds t_a, and corrects by Newton on the bordered system
 *     F(x, lambda) = 0,   c . X = target
 * (c = t_a, target = t_a . X_a + ds: the arclength constraint; c = e_lambda for a point at
 * a fixed lambda), with a fresh forward-difference Jacobian [J F_lambda] every iteration.
 * At a converged point the tangent solves [J F_lambda; t_a^T] t = e_k (unit, oriented
 * along t_a).  Two indicators along the branch:
 *   - t_lambda changes sign at a limit point (the parameter is extremal);
 *   - det [J F_lambda; t^T] changes sign at a simple bifurcation (det J changes sign while
 *     t_lambda does not).
 * A sign change between two points is located by Illinois regula falsi on the arclength
 * from the first, each trial point corrected onto the branch.  At a bifurcation the null
 * vector of [J F_lambda; t^T] is the direction of the crossing branch (inverse iteration).
 * A sign change whose indicator jumps instead of vanishing, a located point where a taut
 * tendon would pass the backbone's centre of curvature (tr_watch_named), and a stall end
 * the path; the message names such a tendon by the rule a stalled solve uses.
 * Every stored point is verified (step doubling, as a solve does) and judged
 * (tr_stability).  Work arrays are allocated once, before the loop; each point gets the
 * solve's work budget afresh; the caller's poll hook is honoured throughout.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tr_internal.h"
#include "tr_path.h"
#include "tru_math.h"

typedef struct {
    int k, n;       /* unknowns, n = k + 1 */
    double *vals;   /* (nt + 6 nl + 3) the value vector (TR_PATH_SLOT) */
    double lam_set; /* lambda whose value is set in the model */
    double *A;      /* (n x n) bordered Jacobian, row-major */
    double *LU;     /* (n x n) LU factors, row-major (tru_lu_factor) */
    int *piv;       /* (n) their row swaps */
    double *F, *X, *Xa, *ta, *t, *c, *Xt, *Xb, *tb; /* (n) each */
    double *r, *dx, *Xs;                            /* (n) each: the corrector's */
    double det_sign;                                /* sign of the last factored determinant */
    double ds;                                      /* the current step along the path */
    double deta, detb; /* det [J F_lambda; t^T] at the last point and at the new one */
    int branch;        /* 0, or 1 after a switch */
    int switched;      /* 1: the step just switched branches */
    int last;          /* 1: the new point is at p1; 2: back at p0 */
    int jump;          /* 1: the last located sign change was a jump (refine) */
    char msg[TR_MSGLEN];
    /* the buffers: one block of doubles and the row swaps, taken from the workspace
     * (tr_data_take: its TR_ALLOC_CALLS reserve, else allocated) */
    double *block;
} path_ws;

static void ws_free(path_ws *w, tr_data *d)
{
    tr_data_drop(d, w->piv);
    tr_data_drop(d, w->block);
}

static int ws_alloc(path_ws *w, const tr_model *m, tr_data *d, const tr_path_spec *sp)
{
    const int n = d->k + 1;
    const size_t n2 = (size_t)n * n;
    int i, c;
    (void)sp;
    memset(w, 0, sizeof *w);
    w->k = d->k;
    w->n = n;
    w->block = (double *)tr_data_take(d, tr_path_len(m->nt, m->nl, d->k) * sizeof(double));
    w->piv = (int *)tr_data_take(d, (size_t)n * sizeof(int));
    if (!w->block || !w->piv) return TR_ENOMEM;
    w->A = w->block;
    w->LU = w->A + n2;
    w->F = w->A + 2 * n2;
    w->X = w->F + n;
    w->Xa = w->X + n;
    w->ta = w->Xa + n;
    w->t = w->ta + n;
    w->c = w->t + n;
    w->Xt = w->c + n;
    w->Xb = w->Xt + n;
    w->tb = w->Xb + n;
    w->r = w->tb + n;
    w->dx = w->r + n;
    w->Xs = w->dx + n;
    w->vals = w->F + 12 * n;
    for (i = 0; i < m->nt; i++) w->vals[i] = m->tendon[i].value;
    for (i = 0; i < m->nl; i++)
        for (c = 0; c < 6; c++) w->vals[m->nt + 6 * i + c] = m->load[TR_LD_NCOL * i + TR_LD_F + c];
    for (c = 0; c < 3; c++) w->vals[m->nt + 6 * m->nl + c] = m->dist[c];
    w->lam_set = 0.0;
    return TR_OK;
}

/* The model's parameter at lambda. */
static int set_lambda(path_ws *w, const tr_model *m, tr_data *d, const tr_path_spec *sp, double lam)
{
    const double p = sp->p0 + lam * (sp->p1 - sp->p0);
    int st;
    if (lam == w->lam_set) return TR_OK;
    if (sp->kind == TR_PATH_SLOT) {
        const int nt = m->nt, idx = sp->index;
        w->vals[idx] = p;
        st = tr_data_set_values(m, d, idx < nt ? w->vals : NULL,
                                idx >= nt && idx < nt + 6 * m->nl ? w->vals + nt : NULL,
                                idx >= nt + 6 * m->nl ? w->vals + nt + 6 * m->nl : NULL, w->msg,
                                sizeof w->msg);
    } else {
        st = tr_inputs_perturb(d, sp->kind, sp->index, p - sp->p0);
        if (st != TR_OK)
            tr_msgf(w->msg, sizeof w->msg, "the parameter at %.10g leaves no valid rest lengths",
                    p);
    }
    if (st != TR_OK) return TR_EINVAL;
    w->lam_set = lam;
    d->y_steps = -1; /* the end state cached in d->y belongs to another value */
    return TR_OK;
}

/* F(X) into w->F (k); TR_OK or the evaluation's failure. */
static int eval(path_ws *w, const tr_model *m, tr_data *d, const tr_path_spec *sp, const double *X)
{
    int st = set_lambda(w, m, d, sp, X[w->k]);
    if (st != TR_OK) return st;
    return tr_residual(m, d, X, w->F);
}

/* The bordered Jacobian [J F_lambda; c^T] at X (F(X) in w->F) into w->A, factored; the
 * sign of its determinant in w->det_sign.  TR_ESINGULAR when exactly singular. */
static int jacobian(path_ws *w, const tr_model *m, tr_data *d, const tr_path_spec *sp,
                    const double *X, const double *c)
{
    const int k = w->k, n = w->n;
    const double lam = X[k], h0 = TR_FD_H * (fabs(lam) > 1.0 ? fabs(lam) : 1.0);
    double h, *ft = d->ft;
    int i, j, st, signum;
    for (j = 0; j < k; j++) {
        st = tr_fd_column(m, d, X, w->F, j, w->A + j, (size_t)n, 1);
        if (st != TR_OK) return st;
    }
    h = (lam + h0) - lam;
    st = set_lambda(w, m, d, sp, lam + h);
    if (st == TR_OK) st = tr_residual(m, d, X, ft);
    if (set_lambda(w, m, d, sp, lam) != TR_OK && st == TR_OK) st = TR_EINVAL;
    if (st != TR_OK) return st;
    for (i = 0; i < k; i++) w->A[i * n + k] = (ft[i] - w->F[i]) / h;
    for (j = 0; j < n; j++) w->A[k * n + j] = c[j];
    memcpy(w->LU, w->A, (size_t)n * n * sizeof(double));
    d->spent += tr_lu_work(n, tr_nonzero_fraction(w->A, n, (size_t)n));
    tru_lu_factor(n, w->LU, n, w->piv, &signum);
    w->det_sign = signum;
    for (i = 0; i < n; i++)
        if (!(w->LU[(size_t)i * n + i] != 0.0)) return TR_ESINGULAR;
    return TR_OK;
}

/* The solution of the factored bordered system with right-hand side r (n) into out. */
static void lu_solve(path_ws *w, const double *r, double *out)
{
    if (out != r) memcpy(out, r, (size_t)w->n * sizeof(double));
    tru_lu_solve(w->n, w->LU, w->n, w->piv, out);
}

static double dot(const double *a, const double *b, int n)
{
    double s = 0.0;
    int i;
    for (i = 0; i < n; i++) s += a[i] * b[i];
    return s;
}

/* A fresh work budget (and time limit) for the next point; the poll clock runs on, so
 * that a path of quick points still polls every TR_POLL_INTERVAL. */
static void point_budget(tr_data *d)
{
    d->spent = 0.0;
    d->t_start = tr_clock();
    d->nfev = 0;
}

/* Newton on F = 0, c . X = target from w->X (in place).  TR_OK when converged (scaled
 * residual <= tol, then one more step kept if it reduces the residual). */
static int correct(path_ws *w, const tr_model *m, tr_data *d, const tr_path_spec *sp,
                   const double *c, double target)
{
    const int k = w->k, n = w->n;
    double fn, fprev = INFINITY, *r = w->r, *dx = w->dx;
    int it, st, i, done = 0;
    for (it = 0; it < TR_PATH_ITER; it++) {
        if (d->stop) return d->stop;
        st = eval(w, m, d, sp, w->X);
        if (st != TR_OK) return st;
        fn = tru_maxnorm(w->F, k);
        /* slow convergence: the step was too long for Newton's basin */
        if (!done && it >= 3 && !(fn <= 0.25 * fprev)) return TR_ENOPROGRESS;
        fprev = fn;
        if (fn <= d->opt.tol && fabs(dot(c, w->X, n) - target) <= d->opt.tol) {
            if (done) break;
            done = 1; /* one more step: the residual well below tol */
        }
        st = jacobian(w, m, d, sp, w->X, c);
        if (st != TR_OK) return done ? TR_OK : st;
        for (i = 0; i < k; i++) r[i] = -w->F[i];
        r[k] = target - dot(c, w->X, n);
        lu_solve(w, r, dx);
        if (!(tru_maxnorm(dx, n) <= TR_PATH_MAX_STEP)) return done ? TR_OK : TR_ENOPROGRESS;
        if (done) {
            /* keep the extra step only if it does not raise the residual */
            for (i = 0; i < n; i++) w->Xs[i] = w->X[i] + dx[i];
            st = eval(w, m, d, sp, w->Xs);
            if (st == TR_OK && tru_maxnorm(w->F, k) <= fn)
                memcpy(w->X, w->Xs, (size_t)n * sizeof(double));
            break;
        }
        for (i = 0; i < n; i++) w->X[i] += dx[i];
    }
    if (!done) {
        tr_set_message(d, "the corrector did not converge in %d Newton iterations", TR_PATH_ITER);
        return TR_EMAXITER;
    }
    /* F at the point kept, for what follows */
    return eval(w, m, d, sp, w->X);
}

/* The unit tangent at w->X (converged, F in w->F) oriented along dir (n) into t, and the
 * sign of det [J F_lambda; t^T] into *det. */
static int tangent(path_ws *w, const tr_model *m, tr_data *d, const tr_path_spec *sp,
                   const double *dir, double *t, double *det)
{
    const int n = w->n;
    double nrm;
    int i, st = jacobian(w, m, d, sp, w->X, dir);
    if (st != TR_OK) return st;
    for (i = 0; i < n; i++) w->Xt[i] = i == n - 1 ? 1.0 : 0.0;
    lu_solve(w, w->Xt, t);
    nrm = sqrt(dot(t, t, n));
    if (!(nrm > 0.0) || !isfinite(nrm)) return TR_ESINGULAR;
    if (dot(t, dir, n) < 0.0) nrm = -nrm;
    for (i = 0; i < n; i++) t[i] /= nrm;
    /* the determinant with the tangent itself in the last row (LU refactored) */
    memcpy(w->LU, w->A, (size_t)(n * n - n) * sizeof(double));
    memcpy(w->LU + (size_t)(n - 1) * n, t, (size_t)n * sizeof(double));
    {
        int signum;
        d->spent += tr_lu_work(n, tr_nonzero_fraction(w->A, n, (size_t)n));
        tru_lu_factor(n, w->LU, n, w->piv, &signum);
        *det = signum;
        for (i = 0; i < n; i++) *det *= fabs(w->LU[(size_t)i * n + i]);
    }
    return TR_OK;
}

/* Verify the point w->X (converged, F in w->F) as a solve does: step doubling (automatic
 * steps), re-solved at lambda fixed when the count is raised.  TR_OK, or why not (a
 * truncation caveat counts as a failure here: the step is retried shorter); d->steps is
 * restored on failure. */
static int verify(path_ws *w, const tr_model *m, tr_data *d, const tr_path_spec *sp)
{
    const int k = w->k, steps = d->steps;
    int st;
    st = set_lambda(w, m, d, sp, w->X[k]);
    if (st != TR_OK) return st;
    memcpy(d->x, w->X, (size_t)k * sizeof(double));
    memcpy(d->f, w->F, (size_t)k * sizeof(double));
    d->fnorm = tru_maxnorm(w->F, k);
    d->truncation = NAN;
    if (d->opt.steps != 0 || d->opt.integrator == TR_ADAPTIVE || tr_verify_carried(m, d))
        return TR_OK;
    st = tr_verify_steps(m, d);
    if (st == TR_OK && d->steps != steps) {
        /* re-solved at the verified step count, lambda fixed */
        memcpy(w->X, d->x, (size_t)k * sizeof(double));
        st = eval(w, m, d, sp, w->X);
    }
    if (st != TR_OK) {
        d->steps = steps;
        d->y_steps = -1;
    }
    return st;
}

/* Judge and store the verified point w->X.  TR_OK, or why not. */
static int store(path_ws *w, const tr_model *m, tr_data *d, const tr_path_spec *sp, tr_path_out *o,
                 int kind, int branch, double tlam)
{
    const int k = w->k, nt = m->nt, row = o->n;
    int st;
    if (row >= o->cap) return TR_ECONTINUATION;
    st = set_lambda(w, m, d, sp, w->X[k]);
    if (st != TR_OK) return st;
    memcpy(d->x, w->X, (size_t)k * sizeof(double));
    st = tr_tip_state(m, d);
    if (st != TR_OK) return st;
    tr_stability(m, d);
    o->par[row] = sp->p0 + w->X[k] * (sp->p1 - sp->p0);
    memcpy(o->tip + 18 * row, d->tip, 18 * sizeof(double));
    memcpy(o->tension + (size_t)nt * row, d->tension, (size_t)nt * sizeof(double));
    memcpy(o->x + (size_t)k * row, w->X, (size_t)k * sizeof(double));
    o->margin[row] = d->stability;
    o->stable[row] = d->stable;
    o->kind[row] = kind;
    o->branch[row] = branch;
    o->tlam[row] = tlam;
    o->steps[row] = d->steps;
    o->residual[row] = tru_maxnorm(w->F, k);
    o->truncation[row] = d->truncation;
    o->n = row + 1;
    /* each point has the work budget of a solve */
    point_budget(d);
    return TR_OK;
}

static double par_of(const tr_path_spec *sp, double lam)
{
    return sp->p0 + lam * (sp->p1 - sp->p0);
}

/* The indicator of a special point of `kind` at a point with tangent t, det sign det. */
static double indicator(int kind, const double *t, double det, int k)
{
    return kind == TR_PT_LIMIT ? t[k] : det;
}

/* Locate the zero of the indicator of `kind` on the step from (Xa, ta), value ga, to the
 * point at arclength sb, value gb; the point found is left in w->X, its tangent in w->t. */
static int refine(path_ws *w, const tr_model *m, tr_data *d, const tr_path_spec *sp, int kind,
                  double ga, double sb, double gb, double *tlam_out)
{
    const int n = w->n, k = w->k;
    const double gmax = fmax(fabs(ga), fabs(gb));
    double a = 0.0, b = sb, s = 0.5 * sb, det, gs = gb, target;
    int it, i, st;
    w->jump = 0;
    for (it = 0; it < TR_PATH_REFINE; it++) {
        s = (a * gb - b * ga) / (gb - ga);
        if (!(s > fmin(a, b) && s < fmax(a, b))) s = 0.5 * (a + b);
        for (i = 0; i < n; i++) w->X[i] = w->Xa[i] + s * w->ta[i];
        target = dot(w->ta, w->Xa, n) + s;
        st = correct(w, m, d, sp, w->ta, target);
        if (st != TR_OK) return st;
        st = tangent(w, m, d, sp, w->ta, w->t, &det);
        if (st == TR_ESINGULAR) {
            /* a corrected trial point where the bordered Jacobian is exactly singular is
             * the point sought (det = 0: a symmetric scene can land on it exactly); the
             * tangent kept is the bracket's */
            memcpy(w->t, w->ta, (size_t)n * sizeof(double));
            gs = 0.0;
            break;
        }
        if (st != TR_OK) return st;
        gs = indicator(kind, w->t, det, k);
        if (gs == 0.0) break;
        if ((gs > 0.0) != (gb > 0.0)) {
            a = b;
            ga = gb;
        } else {
            ga *= 0.5;
        }
        b = s;
        gb = gs;
        if (fabs(b - a) <= TR_PATH_REFINE_TOL * fabs(sb)) break;
    }
    *tlam_out = w->t[k];
    /* a smooth indicator vanishes where it changes sign; one that stays large on both
     * sides of a shrunk bracket jumps: the equations are singular there */
    if (fabs(gs) > TR_PATH_JUMP * gmax) {
        w->jump = 1;
        return TR_ESINGULAR;
    }
    return TR_OK;
}

/* The indicator of `kind` at the point corrected from X_a + s t_a (left in w->X, its
 * tangent in w->t). */
static int indicator_at(path_ws *w, const tr_model *m, tr_data *d, const tr_path_spec *sp, int kind,
                        double s, double *g)
{
    double det;
    int i, st;
    for (i = 0; i < w->n; i++) w->X[i] = w->Xa[i] + s * w->ta[i];
    st = correct(w, m, d, sp, w->ta, dot(w->ta, w->Xa, w->n) + s);
    if (st == TR_OK) st = tangent(w, m, d, sp, w->ta, w->t, &det);
    *g = indicator(kind, w->t, det, w->k);
    return st;
}

/* refine, then again with the steps doubled while the located parameter moves by more
 * than TR_PATH_LOCATE_TOL relative (the truncation error of the linearisation that
 * decides where the indicator vanishes; automatic steps only).  The caller restores
 * d->steps. */
static int locate(path_ws *w, const tr_model *m, tr_data *d, const tr_path_spec *sp, int kind,
                  double ga, double sb, double gb, double *tlam)
{
    double p, prev, g0, g1;
    int st = refine(w, m, d, sp, kind, ga, sb, gb, tlam), round;
    if (st != TR_OK || d->opt.steps != 0 || d->opt.integrator == TR_ADAPTIVE) return st;
    prev = par_of(sp, w->X[w->k]);
    for (round = 0; round < TR_PATH_LOCATE_ROUNDS && 2 * d->steps <= TR_STEP_CAP; round++) {
        d->steps *= 2;
        d->y_steps = -1;
        st = indicator_at(w, m, d, sp, kind, 0.0, &g0);
        if (st == TR_OK) st = indicator_at(w, m, d, sp, kind, sb, &g1);
        if (st != TR_OK) return st;
        if ((g0 > 0.0) == (g1 > 0.0)) break; /* no sign change at the finer count */
        st = refine(w, m, d, sp, kind, g0, sb, g1, tlam);
        if (st != TR_OK) return st;
        p = par_of(sp, w->X[w->k]);
        if (fabs(p - prev) <= TR_PATH_LOCATE_TOL * fabs(p)) break;
        prev = p;
    }
    return TR_OK;
}

/* The null vector of the bordered Jacobian at a bifurcation (factored there, last row the
 * tangent), by two steps of inverse iteration, into z (unit). */
static int null_vector(path_ws *w, const tr_model *m, tr_data *d, const tr_path_spec *sp, double *z)
{
    const int n = w->n;
    double nrm;
    int i, it, st;
    st = jacobian(w, m, d, sp, w->X, w->t);
    if (st != TR_OK && st != TR_ESINGULAR) return st;
    if (st == TR_ESINGULAR) return st;
    for (i = 0; i < n; i++) z[i] = 1.0 + 0.1 * i;
    for (it = 0; it < 3; it++) {
        memcpy(w->Xt, z, (size_t)n * sizeof(double));
        lu_solve(w, w->Xt, z);
        nrm = sqrt(dot(z, z, n));
        if (!(nrm > 0.0) || !isfinite(nrm)) return TR_ESINGULAR;
        for (i = 0; i < n; i++) z[i] /= nrm;
    }
    return TR_OK;
}

/* The start: a solve at p0, its tangent into the span. */
static int path_start(path_ws *w, const tr_model *m, tr_data *d, const tr_path_spec *sp,
                      tr_path_out *o)
{
    const int k = w->k, n = w->n;
    double det;
    int st, i;
    st = tr_solve(m, d, NULL, NULL);
    if (!TR_SUCCEEDED(st)) return st;
    memcpy(w->X, d->x, (size_t)k * sizeof(double));
    w->X[k] = 0.0;
    st = eval(w, m, d, sp, w->X);
    for (i = 0; i < n; i++) w->c[i] = i == k ? 1.0 : 0.0;
    if (st == TR_OK) st = tangent(w, m, d, sp, w->c, w->t, &det);
    if (st != TR_OK) {
        tr_set_message(d, "the start at %.10g has no tangent: %s", sp->p0, tr_strerror(st));
        return TR_ECONTINUATION;
    }
    point_budget(d);
    return store(w, m, d, sp, o, TR_PT_REGULAR, 0, w->t[k]);
}

/* Switch at the bifurcation in w->X onto the crossing branch: its first point in w->X,
 * its tangent in w->t.  ds: the step to take. */
static int switch_branch(path_ws *w, const tr_model *m, tr_data *d, const tr_path_spec *sp,
                         double ds)
{
    const int n = w->n;
    double *z = w->c, big = 0.0, det;
    int i, st, tries;
    st = null_vector(w, m, d, sp, z);
    if (st != TR_OK) return st;
    for (i = 0; i < n - 1; i++)
        if (fabs(z[i]) > fabs(big)) big = z[i];
    if ((big > 0.0) != (sp->side > 0))
        for (i = 0; i < n; i++) z[i] = -z[i];
    memcpy(w->Xa, w->X, (size_t)n * sizeof(double));
    for (tries = 0; tries < 30; tries++, ds *= 0.5) {
        for (i = 0; i < n; i++) w->X[i] = w->Xa[i] + ds * z[i];
        st = correct(w, m, d, sp, z, dot(z, w->Xa, n) + ds);
        if (st == TR_OK) st = tangent(w, m, d, sp, z, w->t, &det);
        if (st == TR_OK) return TR_OK;
        if (d->stop) return d->stop;
    }
    return st;
}

/* The path ends at X, a singular point of the equations or a stall (`what`): if a taut
 * tendon there would pass the backbone's centre of curvature by the rule a stalled solve
 * names it by (tr_watch_named: a path-length rate below TR_WATCH_RATE), the message names
 * the tendon, the arc length, its tension and EI/r^2.  1 when named, else 0 (the message
 * untouched). */
static int ends_at_tendon(path_ws *w, const tr_model *m, tr_data *d, const tr_path_spec *sp,
                          const double *X, const char *what)
{
    char named[TR_MSGLEN];
    const double p = par_of(sp, X[w->k]);
    if (set_lambda(w, m, d, sp, X[w->k]) != TR_OK) return 0;
    if (!tr_watch_named(m, d, X, "there", named, sizeof named)) return 0;
    tr_set_message(d, "the path ends at %.10g: %s; %s", p, named, what);
    return 1;
}

/* d->message = "<head>: <what st means>; <the message so far>". */
static void wrap_message(tr_data *d, int st, const char *head)
{
    char why[TR_MSGLEN];
    memcpy(why, d->message, TR_MSGLEN);
    tr_set_message(d, "%s: %s%s%s", head, tr_strerror(st), why[0] ? "; " : "", why);
}

/* One step from (Xa, ta) with the step w->ds: predict, correct, the tangent tb (det in
 * w->detb), and past the span's end the point exactly at it (w->last: 1 at p1, 2 at p0);
 * then verified.  The point in w->X.  TR_OK, or why the step failed. */
static int take_step(path_ws *w, const tr_model *m, tr_data *d, const tr_path_spec *sp)
{
    const int k = w->k, n = w->n;
    double lamb;
    int i, st, steps;
    w->last = 0;
    for (i = 0; i < n; i++) w->X[i] = w->Xa[i] + w->ds * w->ta[i];
    st = correct(w, m, d, sp, w->ta, dot(w->ta, w->Xa, n) + w->ds);
    if (st == TR_OK) st = tangent(w, m, d, sp, w->ta, w->tb, &w->detb);
    if (st == TR_OK && dot(w->ta, w->tb, n) < TR_PATH_COS) st = TR_ENOPROGRESS;
    lamb = w->X[k];
    if (st == TR_OK && (lamb > 1.0 || lamb < 0.0)) {
        /* the span's end: the point exactly there, from the secant */
        const double lend = lamb > 1.0 ? 1.0 : 0.0, f = (lend - w->Xa[k]) / (lamb - w->Xa[k]);
        for (i = 0; i < n; i++) w->X[i] = w->Xa[i] + f * (w->X[i] - w->Xa[i]);
        for (i = 0; i < n; i++) w->c[i] = i == k ? 1.0 : 0.0;
        st = correct(w, m, d, sp, w->c, lend);
        if (st == TR_OK) st = tangent(w, m, d, sp, w->ta, w->tb, &w->detb);
        if (st == TR_OK) w->last = lend > 0.5 ? 1 : 2;
    }
    if (st != TR_OK) return st;
    steps = d->steps;
    st = verify(w, m, d, sp);
    if (st == TR_OK && d->steps != steps) st = tangent(w, m, d, sp, w->ta, w->tb, &w->detb);
    return st;
}

/* A limit or bifurcation point between Xa and the new point (in w->X, tangent tb),
 * located and stored; at the first bifurcation with sp->side, the switch (w->switched:
 * the new branch's first point stored, in Xa / ta).  Else the new point is in w->X with
 * its tangent in tb again.  TR_OK, or a failure with the message set. */
static int special_between(path_ws *w, const tr_model *m, tr_data *d, const tr_path_spec *sp,
                           tr_path_out *o)
{
    const int k = w->k, n = w->n;
    const int bif = (w->deta > 0.0) != (w->detb > 0.0), lim = (w->ta[k] > 0.0) != (w->tb[k] > 0.0);
    const int kind = bif ? TR_PT_BIFURCATION : TR_PT_LIMIT, steps = d->steps;
    double tlam, sb;
    int st;
    w->switched = 0;
    if (!(bif || lim)) return TR_OK;
    memcpy(w->Xb, w->X, (size_t)n * sizeof(double));
    sb = dot(w->ta, w->Xb, n) - dot(w->ta, w->Xa, n);
    /* a special point has the work budget of a point of its own */
    if (!d->stop) point_budget(d);
    st = locate(w, m, d, sp, kind, kind == TR_PT_LIMIT ? w->ta[k] : w->deta, sb,
                kind == TR_PT_LIMIT ? w->tb[k] : w->detb, &tlam);
    if (st == TR_OK) st = verify(w, m, d, sp);
    /* det J also vanishes where a tendon reaches the centre of curvature (tension EI/r^2
     * at a moment-free end): a singular point, not a special one, where the path ends */
    if (st == TR_OK &&
        ends_at_tendon(w, m, d, sp, w->X,
                       kind == TR_PT_LIMIT
                           ? "the parameter turns there as at a limit point: the equilibrium "
                             "equations are singular there"
                           : "det J vanishes there as at a bifurcation point: the equilibrium "
                             "equations are singular there"))
        st = TR_ECONTINUATION;
    else if (st == TR_OK)
        st = store(w, m, d, sp, o, kind, w->branch, tlam);
    d->steps = steps;
    d->y_steps = -1;
    if (st == TR_ECONTINUATION) return st; /* a tendon at the centre of curvature */
    if (st == TR_ESINGULAR && w->jump) {
        char what[160];
        snprintf(what, sizeof what,
                 "the %s changes sign there without vanishing: the equilibrium equations are "
                 "singular on this branch, not at a %s point",
                 kind == TR_PT_LIMIT ? "tangent's parameter component" : "Jacobian determinant",
                 kind == TR_PT_LIMIT ? "limit" : "bifurcation");
        if (!ends_at_tendon(w, m, d, sp, w->X, what))
            tr_set_message(d,
                           "the path ends at %.10g: %s (no taut tendon is near the "
                           "backbone's centre of curvature there)",
                           par_of(sp, w->X[k]), what);
        return TR_ECONTINUATION;
    }
    if (st != TR_OK) {
        char head[128];
        snprintf(head, sizeof head, "locating the %s point near %.10g failed",
                 kind == TR_PT_LIMIT ? "limit" : "bifurcation", par_of(sp, w->X[k]));
        wrap_message(d, st, head);
        return d->stop ? d->stop : TR_ECONTINUATION;
    }
    if (kind == TR_PT_BIFURCATION && sp->side != 0 && w->branch == 0) {
        st = switch_branch(w, m, d, sp, w->ds);
        if (st == TR_OK) {
            w->branch = 1;
            memcpy(w->Xa, w->X, (size_t)n * sizeof(double));
            memcpy(w->ta, w->t, (size_t)n * sizeof(double));
            st = verify(w, m, d, sp);
        }
        if (st == TR_OK) st = tangent(w, m, d, sp, w->ta, w->t, &w->deta);
        if (st == TR_OK) st = store(w, m, d, sp, o, TR_PT_REGULAR, w->branch, w->ta[k]);
        if (st != TR_OK) {
            char head[128];
            snprintf(head, sizeof head, "the switch at the bifurcation at %.10g failed",
                     o->par[o->n - 1]);
            wrap_message(d, st, head);
            return d->stop ? d->stop : TR_ECONTINUATION;
        }
        w->switched = 1;
        w->last = 0;
        return TR_OK;
    }
    /* the new point again: corrected from the special point toward it */
    memcpy(w->X, w->Xb, (size_t)n * sizeof(double));
    st = correct(w, m, d, sp, w->ta, dot(w->ta, w->Xb, n));
    if (st == TR_OK) st = tangent(w, m, d, sp, w->ta, w->tb, &w->detb);
    return st;
}

/* The final message of a path that ended with st. */
static int end_message(path_ws *w, tr_data *d, const tr_path_spec *sp, const tr_path_out *o, int st)
{
    if (st == TR_EBUDGET || st == TR_EINTERRUPTED) {
        char head[160];
        snprintf(head, sizeof head,
                 "%s after the point at %.10g (each point has the budget of one solve, "
                 "Options.max_work / max_time)",
                 st == TR_EBUDGET ? "the work budget of a point ran out" : "interrupted",
                 o->n > 0 ? o->par[o->n - 1] : sp->p0);
        wrap_message(d, st, head);
    } else if (st == TR_OK && w->last == 2) {
        tr_set_message(d, "the branch returned to the start of the span %.10g", sp->p0);
        st = TR_ECONTINUATION;
    } else if (st == TR_OK) {
        tr_set_message(d, "the path reached %.10g in %d points", sp->p1, o->n);
    }
    return st;
}

int tr_path(const tr_model *m_, tr_data *d, const tr_path_spec *sp, tr_path_out *o)
{
    const tr_model *m = TR_IN(m_, d);
    path_ws w;
    int st;
    o->n = 0;
    if (!(sp->p1 != sp->p0) || !isfinite(sp->p0) || !isfinite(sp->p1) || !(sp->ds0 > 0.0) ||
        !(sp->ds_max >= sp->ds0) || o->cap < 2) {
        tr_set_message(d, "tr_path: span [%g, %g], ds0 = %g, ds_max = %g or cap = %d invalid",
                       sp->p0, sp->p1, sp->ds0, sp->ds_max, o->cap);
        return TR_EINVAL;
    }
    st = ws_alloc(&w, m, d, sp);
    if (st != TR_OK) {
        ws_free(&w, d);
        tr_set_message(d, "tr_path: out of memory");
        return st;
    }
    st = path_start(&w, m, d, sp, o);
    if (st == TR_OK) {
        memcpy(w.Xa, w.X, (size_t)w.n * sizeof(double));
        memcpy(w.ta, w.t, (size_t)w.n * sizeof(double));
        st = tangent(&w, m, d, sp, w.ta, w.t, &w.deta);
        memcpy(w.ta, w.t, (size_t)w.n * sizeof(double));
    }
    w.ds = sp->ds0;
    while (st == TR_OK && !w.last) {
        if (d->stop) {
            st = d->stop;
            break;
        }
        st = take_step(&w, m, d, sp);
        if (st != TR_OK) {
            /* a shorter step, down to TR_PATH_DS_MIN */
            char head[128];
            if (d->stop) {
                st = d->stop;
                break;
            }
            w.ds *= 0.5;
            w.last = 0;
            st = TR_OK;
            if (w.ds >= TR_PATH_DS_MIN) continue;
            snprintf(head, sizeof head, "the path stalled at %.10g (step below %g along the path)",
                     par_of(sp, w.Xa[w.k]), TR_PATH_DS_MIN);
            wrap_message(d, TR_ENOPROGRESS, head);
            /* the last point of a stalled path, walked like the state of a stalled solve */
            {
                char what[TR_MSGLEN];
                snprintf(what, sizeof what, "%s", d->message);
                ends_at_tendon(&w, m, d, sp, w.Xa, what);
            }
            st = TR_ECONTINUATION;
            break;
        }
        st = special_between(&w, m, d, sp, o);
        if (st != TR_OK || w.switched) continue;
        st = store(&w, m, d, sp, o, TR_PT_REGULAR, w.branch, w.tb[w.k]);
        if (st != TR_OK) {
            if (st == TR_ECONTINUATION)
                tr_set_message(d, "the path filled its %d points at %.10g (raise max_points)",
                               o->cap, o->par[o->n - 1]);
            break;
        }
        memcpy(w.Xa, w.X, (size_t)w.n * sizeof(double));
        memcpy(w.ta, w.tb, (size_t)w.n * sizeof(double));
        w.deta = w.detb;
        w.ds = fmin(w.ds * 1.5, sp->ds_max);
    }
    st = end_message(&w, d, sp, o, st);
    ws_free(&w, d);
    return st;
}
