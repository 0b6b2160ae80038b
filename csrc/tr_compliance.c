/*
 * tr_compliance.c -- the linearisation of a solved scene by the implicit function
 * theorem on its shooting map.  With the residual F(x, p) = 0 at the solution x and
 * the poses Y(x, p) at the breakpoints, a parameter p (an actuation value, a probe
 * load, a design value) moves the unknowns by dx/dp = -J^-1 F_p (J = F_x) and the
 * poses by dY/dp = Y_p + Y_x dx/dp.  One pass of differences over the unknowns gives J
 * and Y_x: central (2 k evaluations) or forward (k); each parameter then costs the two
 * evaluations of a central difference that give F_p and Y_p together, none where F_p is
 * known exactly (a prescribed displacement enters only its length residual, a load at
 * the tip only the tip residual).  The compliance is the case of the six probe loads at
 * one breakpoint, by central differences.
 */
#include <math.h>
#include <string.h>

#include "tendonrod.h"
#include "tr_internal.h"

/* What a difference stencil moves: unknown `unknown` (>= 0), or the parameter par.  A
 * tendon's gamma at its switch under the squared slack model (tension tau_s gamma^2, slack
 * l_s gamma^2: both flat at gamma = 0) is moved through xi = gamma |gamma| (`xi`), in which
 * its tension and slack are linear on either side. */
typedef struct {
    int unknown;
    int xi;
    tr_param par;
} lin_dir;

/* The axial and shear rigidities are varied through their compliance c = 1/EA, on which
 * the strains depend linearly (v3 = 1 + n c): a step that changes the strain by about the
 * unknowns' step stays in the linear range however stiff the rod or tendon, where a
 * relative step of EA would change the state by less than its round-off.  The rigidity
 * of parameter p (0 when p is not one of them). */
static double rigidity(const tr_model *m, const tr_param *p)
{
    switch (p->kind) {
    case TR_PAR_ROD_EA: return m->EA;
    case TR_PAR_ROD_GA: return m->GA;
    case TR_PAR_TENDON_EA: return m->tendon[p->index].EA;
    default: return 0.0;
    }
}

/* Step of a parameter's difference stencil for an unknowns' step h: h times the scale the
 * solver measures the quantity by; for a rigidity, a step of its compliance that changes
 * the strain at the scale force (EI/L^2, or the tension scale times L / r for a tendon's
 * stretch against its length residual) by h, at most half the compliance. */
static double param_step(const tr_model *m, const tr_param *p, double h)
{
    const double K = rigidity(m, p);
    if (K > 0.0) {
        const double force = p->kind == TR_PAR_TENDON_EA ? m->tau_s * m->L / m->len_s : m->F_s;
        const double dc = h / force;
        return dc < 0.5 / K ? dc : 0.5 / K;
    }
    switch (p->kind) {
    case TR_PAR_VALUE: return h * (m->tendon[p->index].control == TR_TENSION ? m->tau_s : m->len_s);
    case TR_PAR_LOAD: return h * (p->index % 6 < 3 ? m->F_s : m->M_s);
    case TR_PAR_ROD_EI: return h * m->EI;
    case TR_PAR_ROD_GJ: return h * m->GJ;
    case TR_PAR_OFFSET: return h * m->len_s;
    case TR_PAR_FRICTION: return h;      /* mu is O(0.1-1) */
    default: return h * m->len_s / m->L; /* TR_PAR_SLOPE */
    }
}

/* TR_OK, or TR_EINVAL with a message naming the first parameter this model lacks. */
static int check_params(const tr_model *m, tr_data *d, const tr_param *par, int np, const int *rows,
                        int nrow)
{
    int j, i, pre = 0;
    for (i = 0; i < m->nt; i++)
        if (m->tendon[i].pretension != 0.0) pre = 1;
    if (nrow > m->nseg) {
        tr_set_message(d, "linearise: %d rows for %d breakpoints", nrow, m->nseg);
        return TR_EINVAL;
    }
    for (j = 0; j < nrow; j++)
        if (rows[j] < 1 || rows[j] > m->nseg) {
            tr_set_message(d, "linearise: row %d names breakpoint %d, outside 1..%d", j, rows[j],
                           m->nseg);
            return TR_EINVAL;
        }
    for (j = 0; j < np; j++) {
        const tr_param *p = par + j;
        const int tendon = p->kind == TR_PAR_VALUE || p->kind == TR_PAR_TENDON_EA ||
                           p->kind == TR_PAR_OFFSET || p->kind == TR_PAR_SLOPE ||
                           p->kind == TR_PAR_FRICTION;
        const char *why = NULL;
        if (p->kind < 0 || p->kind >= TR_PAR_NKIND)
            why = "unknown parameter kind";
        else if (tendon && (p->index < 0 || p->index >= m->nt))
            why = "no such tendon";
        else if (p->kind == TR_PAR_LOAD && (p->index < 6 || p->index >= 6 * (m->nseg + 1)))
            why = "a probe load must sit at a breakpoint 1..nseg";
        else if (p->kind == TR_PAR_LOAD && m->planar)
            why = "a probe load needs the spatial formulation (force_spatial)";
        else if ((p->kind == TR_PAR_ROD_EA || p->kind == TR_PAR_ROD_GA) && m->kirchhoff)
            why = "a Kirchhoff rod has no axial or shear rigidity in its model";
        else if (p->kind == TR_PAR_TENDON_EA && !isfinite(m->tendon[p->index].EA))
            why = "an inextensible tendon (EA = inf) has no finite EA to vary";
        else if (p->kind == TR_PAR_FRICTION && m->tendon[p->index].fric_index < 0)
            why = "a frictionless tendon's model has no friction state (give it friction > 0)";
        else if ((p->kind == TR_PAR_OFFSET || p->kind == TR_PAR_SLOPE) && pre)
            why = "the routing of a pretensioned tendon set cannot vary alone (the set would "
                  "lose its balance)";
        if (why) {
            tr_set_message(d, "linearise: parameter %d (kind %d, index %d): %s", j, p->kind,
                           p->index, why);
            return TR_EINVAL;
        }
    }
    return TR_OK;
}

/* The residual f with `dir` moved by delta (dir NULL: at the solution), the poses at the
 * breakpoints captured into pose; everything put back afterwards. */
static int eval_moved(const tr_model *m, tr_data *d, const lin_dir *dir, double delta, double *f,
                      double *pose)
{
    const double *x = d->x;
    double value = 0.0;
    int status, moved = 0;
    if (dir && dir->unknown >= 0) {
        memcpy(d->xt, d->x, (size_t)d->k * sizeof(double));
        if (dir->xi) {
            const double g = d->x[dir->unknown], xi = g * fabs(g) + delta;
            d->xt[dir->unknown] = xi >= 0.0 ? sqrt(xi) : -sqrt(-xi);
        } else {
            d->xt[dir->unknown] += delta;
        }
        x = d->xt;
    } else if (dir && dir->par.kind == TR_PAR_LOAD) {
        d->probe_bp = dir->par.index / 6;
        d->probe[dir->par.index % 6] = delta;
    } else if (dir && dir->par.kind == TR_PAR_VALUE) {
        /* the workspace's input moved, and put back exactly */
        value = d->in.tendon[dir->par.index].value;
        d->in.tendon[dir->par.index].value = value + delta;
        moved = 1;
    } else if (dir) {
        const double K = rigidity(m, &dir->par);
        if (K > 0.0) delta = 1.0 / (1.0 / K + delta) - K; /* a step of the compliance */
        if (tr_inputs_perturb(d, dir->par.kind, dir->par.index, delta) != TR_OK) {
            tr_set_message(d, "linearise: the perturbed tendon set has no rest lengths");
            return TR_EINVAL;
        }
        moved = 2;
    }
    d->capture = pose;
    status = tr_residual(m, d, x, f);
    d->capture = NULL;
    d->probe_bp = -1;
    memset(d->probe, 0, sizeof d->probe);
    if (moved == 1) d->in.tendon[dir->par.index].value = value;
    if (moved == 2) tr_inputs_restore(d);
    return status;
}

/* A difference stencil: central (va - vb) / 2h, first-order (va - v0) / da, or one-sided
 * second-order (-3 v0 + 4 va - vb) / 2 da, from the values at 0, da and db. */
typedef struct {
    int kind; /* 0 central, 1 first order, 2 one-sided second order */
    double da, db;
} lin_stencil;

static double stencil_apply(const lin_stencil *st, double v0, double va, double vb)
{
    if (st->kind == 0) return (va - vb) / (2.0 * st->da);
    if (st->kind == 1) return (va - v0) / st->da;
    return (-3.0 * v0 + 4.0 * va - vb) / (2.0 * st->da);
}

/* The derivative along dir of the residual (col, k) and of the poses at the breakpoints
 * rows (dy, nrow x 6: dx, dtheta), from the solution's residual and poses (d->fs, P0):
 * central differences of step h (side 0) or the one-sided second-order stencil toward
 * side = +1 / -1; with `forward`, first-order differences toward side (+1 for 0). */
static int difference(const tr_model *m, tr_data *d, const lin_dir *dir, double h, int side,
                      int forward, double *col, double *dy, const int *rows, int nrow)
{
    const size_t np = (size_t)12 * (m->nseg + 1);
    const double *P0 = d->lin_pose;
    double *Pa = d->lin_pose + np, *Pb = d->lin_pose + 2 * np;
    lin_stencil st;
    int i, r, q, status;
    st.kind = forward ? 1 : side == 0 ? 0 : 2;
    st.da = (side < 0 ? -1.0 : 1.0) * h;
    st.db = st.kind == 0 ? -h : 2.0 * st.da;
    status = eval_moved(m, d, dir, st.da, d->work, Pa);
    if (status != TR_OK) return status;
    if (st.kind != 1) {
        status = eval_moved(m, d, dir, st.db, d->ft, Pb);
        if (status != TR_OK) return status;
    }
    for (i = 0; i < d->k; i++) col[i] = stencil_apply(&st, d->fs[i], d->work[i], d->ft[i]);
    for (r = 0; r < nrow; r++) {
        const double *p0 = P0 + 12 * rows[r], *pa = Pa + 12 * rows[r], *pb = Pb + 12 * rows[r];
        const double *R0 = p0 + 3;
        double dR[9], W[9];
        for (i = 0; i < 3; i++) dy[6 * r + i] = stencil_apply(&st, p0[i], pa[i], pb[i]);
        for (i = 0; i < 9; i++) dR[i] = stencil_apply(&st, p0[3 + i], pa[3 + i], pb[3 + i]);
        /* W = dR R0^T (skew to first order): dtheta = vee(W) */
        for (i = 0; i < 3; i++)
            for (q = 0; q < 3; q++)
                W[3 * i + q] = dR[3 * i] * R0[3 * q] + dR[3 * i + 1] * R0[3 * q + 1] +
                               dR[3 * i + 2] * R0[3 * q + 2];
        dy[6 * r + 3] = 0.5 * (W[7] - W[5]);
        dy[6 * r + 4] = 0.5 * (W[2] - W[6]);
        dy[6 * r + 5] = 0.5 * (W[3] - W[1]);
    }
    return TR_OK;
}

/* F_p (col) and Y_p (dy) of parameter p where they are known exactly: a prescribed
 * displacement enters only its length residual, E_i / l_s with E_i linear in q_i; a load
 * at the tip only the tip residual, n_b + ... - R^T F (and the moment alike), after the
 * last pose.  1 when known, else 0. */
static int exact_effect(const tr_model *m, tr_data *d, const tr_param *p, double *col, double *dy,
                        int nrow)
{
    int i;
    if (p->kind == TR_PAR_VALUE && m->tendon[p->index].control == TR_DISPLACEMENT) {
        memset(col, 0, (size_t)d->k * sizeof(double));
        col[tr_n_force(m) + m->tendon[p->index].gamma_index] = 1.0 / m->len_s;
    } else if (p->kind == TR_PAR_LOAD && p->index / 6 == m->nseg && !m->planar) {
        const double *R = d->lin_pose + 12 * m->nseg + 3;
        const int q = p->index % 6, c0 = q < 3 ? 0 : 3;
        const double scale = q < 3 ? m->F_s : m->M_s;
        memset(col, 0, (size_t)d->k * sizeof(double));
        for (i = 0; i < 3; i++) col[c0 + i] = -R[3 * (q - c0) + i] / scale;
    } else {
        return 0;
    }
    memset(dy, 0, (size_t)6 * nrow * sizeof(double));
    return 1;
}

/* Which side of its taut/slack switch each tendon's derivatives take: 0 (not near it),
 * +1 (taut side), -1 (slack side), for the gamma unknown or the prescribed tension. */
static int switch_side(const tr_model *m, const tr_data *d, int i)
{
    const tr_tendon *t = &m->tendon[i];
    if (t->control == TR_DISPLACEMENT) {
        const double g = d->x[tr_n_force(m) + t->gamma_index];
        return fabs(g) <= 2.0 * TR_CD_H ? (g >= 0.0 ? 1 : -1) : 0;
    }
    return t->value <= 2.0 * TR_CD_H * m->tau_s ? 1 : 0;
}

/* Columns of J = F_x and Y_x: every unknown, or (only_switched) the gamma unknowns of the
 * tendons whose side is -1 at the switch (a retry on the slack side). */
static int jacobian_columns(const tr_model *m, tr_data *d, const int *rows, int nrow, int forward,
                            int only_switched)
{
    const int k = d->k, off = tr_n_force(m);
    double *dy = d->lin_pose + 36 * ((size_t)m->nseg + 1);
    int i, j, status;
    lin_dir dir;
    dir.par.kind = -1;
    dir.par.index = 0;
    for (j = 0; j < k; j++) {
        int side = 0;
        for (i = 0; i < m->nt; i++)
            if (m->tendon[i].gamma_index >= 0 && off + m->tendon[i].gamma_index == j)
                side = d->lin_side[i];
        if (only_switched && side >= 0) continue;
        dir.unknown = j;
        dir.xi = side != 0 && d->opt.slack_model == TR_SLACK_SQUARED;
        status = difference(m, d, &dir, forward ? TR_LIN_FD_H : TR_CD_H, side, forward, d->xs, dy,
                            rows, nrow);
        if (status != TR_OK) return status;
        for (i = 0; i < k; i++) d->J[i * k + j] = d->xs[i];
        for (i = 0; i < 6 * nrow; i++) d->Yx[(size_t)i * k + j] = dy[i];
    }
    return TR_OK;
}

/* J, Y_x and the LU of J.  A displacement-controlled tendon exactly at its switch is
 * taken on its taut side; where that leaves J singular (the tension of a taut tendon that
 * cannot change the shape, e.g. two inextensible tendons sharing one path, is
 * indeterminate), such tendons are taken on their slack side instead. */
static int factored_jacobian(const tr_model *m, tr_data *d, const int *rows, int nrow, int forward)
{
    int i, moved = 0, status = jacobian_columns(m, d, rows, nrow, forward, 0);
    if (status != TR_OK) return status;
    d->njev++;
    if (tr_lu_factor(d) == 0) return TR_OK;
    for (i = 0; i < m->nt; i++)
        if (m->tendon[i].control == TR_DISPLACEMENT && d->lin_side[i] > 0) {
            d->lin_side[i] = -1;
            moved = 1;
        }
    if (!moved) return TR_ESINGULAR;
    status = jacobian_columns(m, d, rows, nrow, forward, 1);
    if (status != TR_OK) return status;
    return tr_lu_factor(d) == 0 ? TR_OK : TR_ESINGULAR;
}

/* Tendon i's tension and slack rates (dt [N], db [m] per unit of parameter p) from the
 * unknowns' rates in d->xp: a tension-controlled tendon's tension is its value; a
 * displacement-controlled one moves with its gamma on the side it is on (its xi = gamma
 * |gamma| at the switch under the squared model). */
static void tendon_rates(const tr_model *m, const tr_data *d, const tr_param *p, int i, double *dt,
                         double *db)
{
    const tr_tendon *t = &m->tendon[i];
    *dt = *db = 0.0;
    if (t->control == TR_TENSION) {
        *dt = p->kind == TR_PAR_VALUE && p->index == i ? 1.0 : 0.0;
    } else {
        const int off = tr_n_force(m), side = d->lin_side[i];
        const double g = d->x[off + t->gamma_index], dg = d->xp[off + t->gamma_index];
        const double f = d->opt.slack_model == TR_SLACK_SQUARED && side == 0 ? 2.0 * fabs(g) : 1.0;
        if (side > 0 || (side == 0 && g > 0.0))
            *dt = m->tau_s * dg * f;
        else
            *db = -m->len_s * dg * f;
    }
}

static int linearize(const tr_model *m, tr_data *d, const tr_param *par, int np, const int *rows,
                     int nrow, double *dpose, double *dtension, double *dslack, const int *want,
                     int forward)
{
    const int k = d->k;
    int i, j, r, c, status;
    lin_dir dir;
    for (i = 0; i < m->nt; i++) {
        /* the side asked for, for a displacement-controlled tendon at its switch */
        const int side = switch_side(m, d, i);
        const int asked =
            want && side != 0 && m->tendon[i].control == TR_DISPLACEMENT ? want[i] : 0;
        d->lin_side[i] = asked > 0 ? 1 : asked < 0 ? -1 : side;
    }
    status = eval_moved(m, d, NULL, 0.0, d->fs, d->lin_pose);
    if (status != TR_OK) return status;
    status = factored_jacobian(m, d, rows, nrow, forward);
    if (status != TR_OK) return status;
    /* each parameter: F_p, Y_p; dx = -J^-1 F_p; dY = Y_p + Y_x dx */
    for (j = 0; j < np; j++) {
        const tr_param *p = par + j;
        double *out = dpose + (size_t)j * nrow * 6;
        if (!exact_effect(m, d, p, d->xs, out, nrow)) {
            const int side = p->kind == TR_PAR_VALUE && m->tendon[p->index].control == TR_TENSION
                                 ? d->lin_side[p->index]
                                 : 0;
            const double K = rigidity(m, p);
            dir.unknown = -1;
            dir.xi = 0;
            dir.par = *p;
            status =
                difference(m, d, &dir, param_step(m, p, TR_CD_H), side, 0, d->xs, out, rows, nrow);
            if (status != TR_OK) return status;
            if (K > 0.0) { /* d/dK = -d/dc / K^2 */
                for (i = 0; i < k; i++) d->xs[i] *= -1.0 / (K * K);
                for (r = 0; r < 6 * nrow; r++) out[r] *= -1.0 / (K * K);
            }
        }
        for (i = 0; i < k; i++) d->xs[i] = -d->xs[i];
        if (tr_lu_solve(d, d->xs, d->xp) != 0) return TR_ESINGULAR;
        for (r = 0; r < 6 * nrow; r++) {
            double s = 0.0;
            for (c = 0; c < k; c++) s += d->Yx[(size_t)r * k + c] * d->xp[c];
            out[r] += s;
        }
        for (i = 0; i < m->nt; i++) {
            double dt, db;
            tendon_rates(m, d, p, i, &dt, &db);
            if (dtension) dtension[(size_t)j * m->nt + i] = dt;
            if (dslack) dslack[(size_t)j * m->nt + i] = db;
        }
    }
    return TR_OK;
}

int tr_linearize(const tr_model *m_, tr_data *d, const tr_param *par, int np, const int *rows,
                 int nrow, double *dpose, double *dtension, double *dslack, int *at_switch,
                 int scheme)
{
    const tr_model *m = TR_IN(m_, d);
    int i, status, scratch = 0;
    if (np < 0 || nrow < 0 || (np > 0 && !par) || (nrow > 0 && !rows) ||
        (np > 0 && nrow > 0 && !dpose)) {
        tr_set_message(d, "linearise: invalid arguments (negative count or NULL array)");
        return TR_EINVAL;
    }
    status = check_params(m, d, par, np, rows, nrow);
    if (status != TR_OK) return status;
    /* a value or a design perturbed in the workspace's own inputs (not a nested view) */
    for (i = 0; i < np; i++)
        if (par[i].kind != TR_PAR_LOAD &&
            !(par[i].kind == TR_PAR_VALUE && m->tendon[par[i].index].control == TR_DISPLACEMENT))
            scratch = 1;
    if (scratch && d->vm != &d->in) {
        tr_set_message(d, "linearise: a nested workspace has no inputs of its own");
        return TR_EINVAL;
    }
    d->lam_act = d->lam_load = d->lam_hom = 1.0;
    tr_poll_start(d); /* a budget of its own; the caller's interrupt still applies */
    status = linearize(m, d, par, np, rows, nrow, dpose, dtension, dslack, at_switch,
                       scheme == TR_DIFF_FORWARD);
    for (i = 0; at_switch && i < m->nt; i++) at_switch[i] = d->lin_side[i];
    tr_set_tensions(m, d, d->x);
    if (status == TR_EBUDGET)
        tr_set_message(d,
                       "the work budget ran out while linearising (max_work = %.3g units; the "
                       "linearisation needs about 2 k + 2 p evaluations, k = %d unknowns, p = %d "
                       "parameters): raise Options.max_work",
                       d->opt.max_work, d->k, np);
    else if (status == TR_ESINGULAR)
        tr_set_message(d, "linearise: the Jacobian at the solution is singular");
    else if (status != TR_OK && status != TR_EINVAL && status != TR_EINTERRUPTED)
        tr_set_message(d, "linearisation failed: %s", tr_strerror(status));
    return status;
}

int tr_compliance(const tr_model *m_, tr_data *d, double s_probe, double C[36])
{
    const tr_model *m = TR_IN(m_, d);
    tr_param par[6];
    double dpose[36];
    int pb = -1, b, q, i, status;
    for (b = 1; b <= m->nseg; b++)
        if (fabs(m->bp[b] - s_probe) <= 1e-12 * m->L) pb = b;
    if (pb < 0) {
        tr_set_message(d,
                       "compliance: s = %g m is not a breakpoint of the model (add a zero "
                       "point load there)",
                       s_probe);
        return TR_EINVAL;
    }
    if (m->planar) {
        tr_set_message(d, "compliance needs the spatial formulation (force_spatial)");
        return TR_EINVAL;
    }
    for (q = 0; q < 6; q++) {
        par[q].kind = TR_PAR_LOAD;
        par[q].index = 6 * pb + q;
    }
    status = tr_linearize(m, d, par, 6, &pb, 1, dpose, NULL, NULL, NULL, TR_DIFF_CENTRAL);
    if (status == TR_ESINGULAR)
        tr_set_message(d, "compliance: the Jacobian at the solution is singular");
    else if (status == TR_EBUDGET)
        tr_set_message(d,
                       "the work budget ran out while linearising (max_work = %.3g units; the "
                       "compliance needs 2 k + 12 evaluations, k = %d unknowns): raise "
                       "Options.max_work",
                       d->opt.max_work, d->k);
    if (status != TR_OK) return status;
    for (q = 0; q < 6; q++)
        for (i = 0; i < 6; i++) C[6 * i + q] = dpose[6 * q + i];
    return TR_OK;
}
