/*
 * tr_data.c -- the workspace of one solve: everything that changes, allocated here and
 * freed in tr_data_free.  With TR_ALLOC_ALL nothing in between: the stability test's grid
 * workspaces with room for the finest grid the test refines to (tr_stab_workspace, below,
 * sets a grid in place) and the confirmation's second formulation come with it; without,
 * the first solve that needs them allocates them (tr_stab_workspace, tr_confirm.c); and
 * room for the buffers of the largest tr_path and tr_actuate call of the model, which the
 * calls take (tr_data_take) and allocate only on a workspace without it.  The workspace's
 * inputs (the values its solves use) are tr_inputs.c's.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <gsl/gsl_errno.h>

#include "tendonrod.h"
#include "tr_internal.h"
#include "tr_qp.h"
#include "tr_stab.h"

static tr_data *data_alloc(const tr_model *m, const tr_options *opt, int nnode,
                           const double *node_s, int nested, int flags, char *msg, size_t msglen);

/* ------------------------------------------------------------ the stability test's grid */
void tr_stab_free(struct tr_stab_ws *w)
{
    if (!w) return;
    tr_data_free(w->rec);
    free(w->s);
    free(w->kind); /* with node */
    free(w->R);    /* with every other array */
    free(w);
}

/* The doubles of a grid's arrays: cap nodes of nb coordinates, nt tendons. */
static size_t stab_len(size_t cap, size_t nb, size_t nt)
{
    const size_t nblk = cap * nb * nb, nv = cap * nb;
    return 18 * cap + nt + 2 * nv + 5 * nblk + 2 * nv + 2 * nv * nt + 2 * nt + 2 * nt * nt +
           10 * nv;
}

size_t tr_stab_len(size_t cap, size_t nb, size_t nt)
{
    return stab_len(cap, nb, nt > 0 ? nt : 1);
}

/* The arrays of the grid w holds (cap nodes of w->nb coordinates) laid out one after the
 * other from the start of its blocks, as a workspace allocated for that grid alone had
 * them, and zeroed as such a one was (the blocks hold room for the finest grid; a grid
 * touches only what it uses); the recording workspace's node arrays likewise over its
 * nodes. */
void tr_stab_layout(const tr_model *m, struct tr_stab_ws *w, size_t cap)
{
    const size_t nb = (size_t)w->nb;
    const size_t nt = (size_t)(m->nt > 0 ? m->nt : 1), nblk = cap * nb * nb, nv = cap * nb;
    double *q;
    w->node = w->kind + cap;
    w->col = w->node + cap;
    memset(w->R, 0, stab_len(cap, nb, nt) * sizeof(double));
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
    w->h.Sv = q, q += nt * nt;
    if (nt * nt > nblk) {
        /* many tendons on a short grid: the Schur complement gets its own space */
        w->h.S = q;
    }
    q += nt * nt;
    w->sw_buf = q; /* 10 nv */
    if (w->rec) {
        tr_data *r = w->rec;
        const size_t n = (size_t)w->ngrid;
        r->pos = r->s + n;
        r->rot = r->s + 4 * n;
        r->force = r->s + 13 * n;
        r->moment = r->s + 16 * n;
        r->node_tension = r->s + 19 * n;
        r->node_rest = r->node_tension + (size_t)m->nt * n;
        memset(r->pos, 0, (18 + 2 * (size_t)m->nt) * n * sizeof(double));
    }
}

/* The grid of nuni uniform elements into w: those nodes and every breakpoint, sorted,
 * merged within 1e-12 L; its recording workspace set to record there (no allocation:
 * w holds room for the finest grid). */
static void stab_grid(const tr_model *m, struct tr_stab_ws *w, int nuni, int cosserat, int zero)
{
    int i, b, n = 0;
    w->nuni = nuni, w->nb = cosserat ? 6 : 3, w->cosserat = cosserat;
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
    if (zero) tr_stab_layout(m, w, (size_t)w->nuni + m->nseg + 2);
    if (w->rec) {
        w->rec->nnode = n;
        for (i = 0; i < n; i++) w->rec->s[i] = w->s[i] > m->L ? m->L : w->s[i];
    }
}

/* A grid workspace with room for the finest grid the test refines to (TR_STAB_MAX_ELEMENTS
 * uniform elements, Cosserat: 6 coordinates per node), set to nuni elements.  The large
 * blocks are only touched as far as a grid uses them. */
static struct tr_stab_ws *stab_alloc(const tr_model *m, const tr_options *opt, int nuni,
                                     int cosserat, int cap_nuni, int cap_nb)
{
    struct tr_stab_ws *w = (struct tr_stab_ws *)calloc(1, sizeof *w);
    const int cap = cap_nuni + m->nseg + 2, nt = m->nt > 0 ? m->nt : 1;
    char msg[TR_MSGLEN];
    tr_options o = *opt;
    if (!w) return NULL;
    w->s = (double *)malloc((size_t)cap * sizeof(double));
    w->kind = (int *)malloc(((size_t)cap * 2 + nt) * sizeof(int));
    /* zeroed per grid as far as it is used (stab_layout) */
    w->R = (double *)malloc(stab_len((size_t)cap, (size_t)cap_nb, (size_t)nt) * sizeof(double));
    if (!w->s || !w->kind || !w->R) {
        tr_stab_free(w);
        return NULL;
    }
    w->cap_nuni = cap_nuni, w->cap_nb = cap_nb;
    /* the recording workspace allocated on the finest grid, then set to this one */
    stab_grid(m, w, cap_nuni, cap_nb == 6, 0);
    o.tip_only = 0;
    w->rec = data_alloc(m, &o, w->ngrid, w->s, 2, 0, msg, sizeof msg);
    if (!w->rec) {
        tr_stab_free(w);
        return NULL;
    }
    stab_grid(m, w, nuni, cosserat, 1);
    return w;
}

/* The workspace *wp set to nuni uniform elements: in place when it has room (allocated with
 * the workspace: TR_ALLOC_GRIDS the first grids, TR_ALLOC_FINEST the finest), else allocated
 * here (a workspace without them, or a finer grid than it has room for). */
struct tr_stab_ws *tr_stab_workspace(const tr_model *m_, tr_data *d, struct tr_stab_ws **wp,
                                     int nuni, int cosserat)
{
    const tr_model *m = TR_IN(m_, d);
    struct tr_stab_ws *w = *wp;
    if (nuni > TR_STAB_MAX_ELEMENTS) return NULL;
    if (w && (w->nuni != nuni || w->cosserat != cosserat) &&
        (nuni > w->cap_nuni || (cosserat ? 6 : 3) > w->cap_nb)) {
        /* finer than it has room for (a workspace without TR_ALLOC_FINEST): a new one */
        tr_stab_free(w);
        w = *wp = NULL;
    }
    if (!w)
        *wp = stab_alloc(m, &d->opt, nuni, cosserat, nuni, cosserat ? 6 : 3);
    else if (w->nuni != nuni || w->cosserat != cosserat)
        stab_grid(m, w, nuni, cosserat, 1);
    return *wp;
}

void tr_data_free(tr_data *d)
{
    if (!d) return;
    free(d->x);
    free(d->J);
    free(d->LU);
    free(d->piv);
    free(d->tau);
    free(d->fric_done);
    free(d->val_ver);
    free(d->y);
    if (d->rk8_shoot) gsl_odeiv2_step_free(d->rk8_shoot);
    if (d->rk8_rec) gsl_odeiv2_step_free(d->rk8_rec);
    if (d->ad_step_shoot) gsl_odeiv2_step_free(d->ad_step_shoot);
    if (d->ad_step_rec) gsl_odeiv2_step_free(d->ad_step_rec);
    if (d->ad_ctl_shoot) gsl_odeiv2_control_free(d->ad_ctl_shoot);
    if (d->ad_ctl_rec) gsl_odeiv2_control_free(d->ad_ctl_rec);
    if (d->ad_ev_shoot) gsl_odeiv2_evolve_free(d->ad_ev_shoot);
    if (d->ad_ev_rec) gsl_odeiv2_evolve_free(d->ad_ev_rec);
    free(d->Yx);
    free(d->calls);
    tr_inputs_free(d);
    free(d->x_last);
    free(d->x_guess);
    tr_data_free(d->confirm_d);
    tr_stab_free(d->stab);
    tr_stab_free(d->stab_quick);
    tr_model_free(d->confirm_m);
    free(d->lin_C);
    free(d->lin_act);
    free(d->bp_pose);
    if (d->hyb) gsl_multiroot_fdfsolver_free(d->hyb);
    free(d->s);
    free(d);
}

/* The named buffers, carved out of a few blocks.  0, or -1 when out of memory. */
static int alloc_buffers(const tr_model *m, tr_data *d)
{
    const int k = d->k, nsr = m->n_states_rec, nt = m->nt, nd = m->ndisp;
    d->x = (double *)calloc((size_t)13 * k + 1, sizeof(double));
    d->J = (double *)calloc((size_t)k * k + 1, sizeof(double));
    d->x_last = (double *)calloc((size_t)k * (k + 3) + 1, sizeof(double));
    d->LU = (double *)calloc((size_t)k * k + 1, sizeof(double));
    d->piv = (int *)calloc((size_t)k + 1, sizeof(int));
    d->tau = (double *)calloc((size_t)6 * nt + (TR_FRIC_NCOL + 9) * (size_t)m->nfric + 1,
                              sizeof(double));
    d->fric_done = (int *)calloc((size_t)m->nfric + 1, sizeof(int));
    d->val_ver = (double *)calloc((size_t)2 * nt + 1, sizeof(double));
    d->y = (double *)calloc((size_t)10 * nsr, sizeof(double));
    d->Yx = (double *)calloc((size_t)6 * m->nseg * k + 42 * ((size_t)m->nseg + 1), sizeof(double));
    d->lin_C = (double *)calloc((size_t)(2 * nd * nd + 4 * nd + 1), sizeof(double));
    d->lin_act = (int *)calloc((size_t)(3 * nd + nt + 1), sizeof(int));
    d->x_guess =
        (double *)calloc((size_t)4 * k + nt + 7 * ((size_t)m->nseg + 1) + 4, sizeof(double));
    d->bp_pose = (double *)calloc((size_t)12 * (m->nseg + 1), sizeof(double));
    if (!d->bp_pose || !d->lin_C || !d->lin_act || !d->x || !d->J || !d->LU || !d->piv || !d->tau ||
        !d->y || !d->Yx || !d->x_last || !d->x_guess || !d->fric_done || !d->val_ver)
        return -1;
    d->f_guess = d->x_guess + k;
    d->x_alt = d->x_guess + 2 * k;
    d->carry_x = d->x_guess + 3 * k;
    d->carry_val = d->x_guess + 4 * k;
    d->J_last = d->x_last + k;
    d->x_ver = d->J_last + k * k;
    d->x_ver_last = d->x_ver + k;
    d->f = d->x + k;
    d->xt = d->x + 2 * k;
    d->ft = d->x + 3 * k;
    d->dx = d->x + 4 * k;
    d->xs = d->x + 5 * k;
    d->xp = d->x + 6 * k;
    d->fs = d->x + 7 * k;
    d->work = d->x + 8 * k;
    d->hyb_f = d->x + 9 * k;
    d->x_of_y = d->x + 10 * k;
    d->f_of_y = d->x + 11 * k;
    d->x_J = d->x + 12 * k;
    d->y_steps = -1;
    d->beta = d->tau + nt;
    d->tension = d->tau + 2 * nt;
    d->slack = d->tau + 3 * nt;
    d->displacement = d->tau + 4 * nt;
    d->tau_here = d->tau + 5 * nt;
    d->fric_ws = d->tau + 6 * nt;
    d->val_ver_last = d->val_ver + nt;
    d->fric_g = d->fric_ws + TR_FRIC_NCOL * m->nfric;
    d->k1 = d->y + nsr;
    d->k2 = d->y + 2 * nsr;
    d->k3 = d->y + 3 * nsr;
    d->k4 = d->y + 4 * nsr;
    d->yt = d->y + 5 * nsr;
    d->yerr = d->y + 6 * nsr;
    d->ysave = d->y + 7 * nsr;
    d->ysw = d->y + 8 * nsr;
    d->lin_pose = d->Yx + (size_t)6 * m->nseg * k;
    d->lin_A = d->lin_C + nd * nd;
    d->lin_rhs = d->lin_A + nd * nd;
    d->lin_sol = d->lin_rhs + nd;
    d->lin_pre = d->lin_sol + nd;
    d->lin_tmp = d->lin_pre + nd;
    d->lin_map = d->lin_act + nd;
    d->switched = d->lin_map + nd;
    d->lin_side = d->switched + nd;
    return 0;
}

/* ODE systems and steppers of both layouts (shooting, recording); the adaptive
 * ones only for the adaptive integrator.  0, or -1 when out of memory. */
static int alloc_integrators(const tr_model *m, tr_data *d, const tr_options *opt)
{
    const int nsr = m->n_states_rec;
    double *scale;
    int i;
    d->sys_shoot.function = tr_rhs;
    d->sys_shoot.jacobian = NULL;
    d->sys_shoot.dimension = (size_t)m->n_states;
    d->sys_shoot.params = d;
    d->sys_rec = d->sys_shoot;
    d->sys_rec.dimension = (size_t)nsr;
    d->rk8_shoot = gsl_odeiv2_step_alloc(gsl_odeiv2_step_rk8pd, m->n_states);
    d->rk8_rec = gsl_odeiv2_step_alloc(gsl_odeiv2_step_rk8pd, nsr);
    if (!d->rk8_shoot || !d->rk8_rec) return -1;
    if (opt->integrator != TR_ADAPTIVE) return 0;
    scale = (double *)malloc((size_t)nsr * sizeof(double));
    if (!scale) return -1;
    for (i = 0; i < nsr; i++) scale[i] = i < m->n_base ? m->xstate_scale[i] : m->L;
    d->ad_step_shoot = gsl_odeiv2_step_alloc(gsl_odeiv2_step_rk8pd, m->n_states);
    d->ad_step_rec = gsl_odeiv2_step_alloc(gsl_odeiv2_step_rk8pd, nsr);
    /* error per component <= rtol * (scale_i + |y_i|) */
    d->ad_ctl_shoot =
        gsl_odeiv2_control_scaled_new(opt->rtol, opt->rtol, 1.0, 0.0, scale, m->n_states);
    d->ad_ctl_rec = gsl_odeiv2_control_scaled_new(opt->rtol, opt->rtol, 1.0, 0.0, scale, nsr);
    d->ad_ev_shoot = gsl_odeiv2_evolve_alloc(m->n_states);
    d->ad_ev_rec = gsl_odeiv2_evolve_alloc(nsr);
    free(scale);
    if (!d->ad_step_shoot || !d->ad_step_rec || !d->ad_ctl_shoot || !d->ad_ctl_rec ||
        !d->ad_ev_shoot || !d->ad_ev_rec)
        return -1;
    return 0;
}

/* Merge the uniform grid of nnode nodes with each interior breakpoint: twice where a
 * load or an anchor makes a jump (before and after it), once at a shooting node.
 * Returns the number of nodes written (at most nn). */
static int merge_nodes(const tr_model *m, int nnode, double *s, int nn)
{
    int iu = 0, ib = 1, o = 0;
    while ((iu < nnode || ib < m->nseg) && o < nn) {
        const double su =
            iu < nnode ? (iu == nnode - 1 ? m->L : m->L * ((double)iu / (nnode - 1))) : INFINITY;
        const double sb = ib < m->nseg ? m->bp[ib] : INFINITY;
        if (ib < m->nseg && sb <= su && o + 2 <= nn) {
            s[o++] = sb;
            if (m->bp_jump[ib]) s[o++] = sb;
            ib++;
            if (fabs(su - sb) <= 1e-12 * m->L) iu++;
        } else if (iu < nnode) {
            s[o++] = su;
            iu++;
        } else {
            break;
        }
    }
    return o;
}

/* The output nodes and their arrays (s, the 18 recorded states, the nt tendon tensions and
 * rest lengths per node, in one block).  0, or -1 when out of memory. */
static int alloc_nodes(const tr_model *m, tr_data *d, int nnode, const double *node_s, int zero)
{
    int i, nn;
    if (d->opt.tip_only)
        nn = 1;
    else if (node_s)
        nn = nnode;
    else
        nn = nnode + 2 * (m->nseg - 1); /* upper bound; the merge sets the count */
    d->s = zero ? (double *)calloc((size_t)nn * (19 + 2 * m->nt), sizeof(double))
                : (double *)malloc((size_t)nn * (19 + 2 * m->nt) * sizeof(double));
    if (!d->s) return -1;
    d->node_tension = d->s + 19 * nn;
    d->node_rest = d->node_tension + (size_t)m->nt * nn;
    d->pos = d->s + nn;
    d->rot = d->s + 4 * nn;
    d->force = d->s + 13 * nn;
    d->moment = d->s + 16 * nn;
    if (d->opt.tip_only)
        d->s[0] = m->L;
    else if (node_s)
        for (i = 0; i < nn; i++) d->s[i] = node_s[i] > m->L ? m->L : node_s[i];
    else
        nn = merge_nodes(m, nnode, d->s, nn);
    d->nnode = nn;
    return 0;
}

static int check_nodes(const tr_model *m, const tr_options *opt, int nnode, const double *node_s,
                       char *msg, size_t msglen)
{
    int i;
    if (!node_s && !opt->tip_only && (nnode < 2 || nnode > TR_MAX_NODES)) {
        tr_msgf(msg, msglen, "nodes = %d must lie in [2, %d] (0 and L included)", nnode,
                TR_MAX_NODES);
        return TR_EINVAL;
    }
    if (!node_s) return TR_OK;
    if (nnode < 1 || nnode > TR_MAX_NODES) {
        tr_msgf(msg, msglen, "the number of node arc lengths (%d) must lie in [1, %d]", nnode,
                TR_MAX_NODES);
        return TR_EINVAL;
    }
    for (i = 0; i < nnode; i++)
        if (!(node_s[i] >= 0.0 && node_s[i] <= m->L * (1.0 + 1e-12)) ||
            (i > 0 && node_s[i] < node_s[i - 1])) {
            tr_msgf(msg, msglen, "nodes[%d] = %g must be sorted and within [0, L = %g]", i,
                    node_s[i], m->L);
            return TR_EINVAL;
        }
    return TR_OK;
}

/* The second formulation that confirms an equilibrium found off the load path (tr_confirm.c):
 * the scene compiled with TR_CONFIRM_SEGMENTS shooting segments (twice the model's from
 * there on), its workspace tip-only and without nested workspaces of its own (a workspace
 * that confirms does not confirm in turn, nor judge stability).  None when no finer
 * formulation exists.  0, or -1 when it could not be set up (msg says why). */
int tr_data_alloc_confirm(const tr_model *m, tr_data *d, char *msg, size_t msglen)
{
    const int M = m->nshoot, M2 = M >= TR_CONFIRM_SEGMENTS ? 2 * M : TR_CONFIRM_SEGMENTS;
    tr_options o = d->opt;
    if (M2 > TR_MAX_SHOOTING_SEGMENTS) return 0;
    o.shooting_segments = M2;
    o.tip_only = 1;
    d->confirm_m = tr_model_reshoot(m, &o, M2, msg, msglen);
    if (!d->confirm_m) return -1;
    d->confirm_d = data_alloc(d->confirm_m, &o, 1, NULL, 1, 0, msg, msglen);
    return d->confirm_d ? 0 : -1;
}

/* ------------------------------------------------------------ a call's buffers */
static size_t round16(size_t bytes)
{
    return (bytes + 15) / 16 * 16;
}

size_t tr_path_len(int nt, int nl, int k)
{
    const size_t n = (size_t)k + 1;
    /* the value vector, the bordered Jacobian and its LU, 12 n-vectors */
    return (size_t)nt + 6 * (size_t)nl + 3 + 2 * n * n + 12 * n;
}

size_t tr_act_run_len(int nt, int k, int n, int mt)
{
    const int ls = nt + mt > n ? nt + mt : n;
    const size_t per = (size_t)(6 + 2 * nt) + 2 * (size_t)k + (size_t)k * k + 3 * (size_t)nt + n;
    return ACT_POOL * per + (size_t)k * k + nt + n + 6 * (size_t)nt + 2 * (size_t)nt * nt +
           tr_lstsq_work_len(ls, n);
}

size_t tr_act_iter_len(int nt_, int n_, int mt_, size_t *ilen)
{
    const size_t n = (size_t)n_, nt = (size_t)nt_, mt = (size_t)mt_, gmax = nt + 5 * n + 1;
    *ilen = 5 * nt + n + gmax;
    return 16 * n + 5 * n * n + (mt + nt + gmax) * n + 2 * gmax + (mt + nt) * n + mt + nt + 7 * nt +
           6 + tr_qp_work_len(n_, mt_, (int)gmax);
}

/* The reserve of TR_ALLOC_CALLS: the larger of a path's buffers and an actuation's with
 * every tendon a control and a target of 6 components (the most a call of this model can
 * take: the lengths grow with both). */
static int alloc_calls(const tr_model *m, tr_data *d)
{
    const int nt = m->nt, k = d->k;
    size_t ilen, path, act;
    path = round16(tr_path_len(nt, m->nl, k) * sizeof(double)) +
           round16(((size_t)k + 1) * sizeof(int));
    act = round16(tr_act_run_len(nt, k, nt, 6) * sizeof(double)) +
          round16(((size_t)nt + 1) * sizeof(tr_param));
    act +=
        round16(tr_act_iter_len(nt, nt, 6, &ilen) * sizeof(double)) + round16(ilen * sizeof(int));
    d->calls_len = path > act ? path : act;
    d->calls = (double *)malloc(d->calls_len);
    return d->calls ? 0 : -1;
}

void *tr_data_take(tr_data *d, size_t bytes)
{
    const size_t b = round16(bytes ? bytes : 1);
    if (d->calls && b <= d->calls_len - d->calls_used) {
        char *p = (char *)d->calls + d->calls_used;
        d->calls_used += b;
        memset(p, 0, b);
        return p;
    }
    return calloc(1, b);
}

void tr_data_drop(tr_data *d, void *p)
{
    const char *base = (const char *)d->calls, *q = (const char *)p;
    if (!p) return;
    if (base && q >= base && q < base + d->calls_len) {
        const size_t off = (size_t)(q - base);
        if (off < d->calls_used) d->calls_used = off;
    } else {
        free(p);
    }
}

/* nested: 0 a caller's workspace (with TR_ALLOC_GRIDS or _FINEST the stability test's grids
 * unless accept_unstable, with TR_ALLOC_CONFIRM the confirmation's workspace when
 * continuation may need it), 1 a confirming one
 * (neither), 2 a grid's recording (neither; its node arrays left for stab_zero to clear as
 * far as a grid uses them).  A workspace of another workspace's view has neither. */
static tr_data *data_alloc(const tr_model *m, const tr_options *opt, int nnode,
                           const double *node_s, int nested, int flags, char *msg, size_t msglen)
{
    tr_data *d;
    if (msg && msglen) msg[0] = '\0';
    if (!m || !opt) {
        tr_msgf(msg, msglen, "tr_data_alloc: NULL model or options");
        return NULL;
    }
    if (tr_options_check(opt, msg, msglen) != TR_OK ||
        check_nodes(m, opt, nnode, node_s, msg, msglen) != TR_OK)
        return NULL;
    d = (tr_data *)calloc(1, sizeof *d);
    if (!d) {
        tr_msgf(msg, msglen, "out of memory");
        return NULL;
    }
    d->model = m;
    d->opt = *opt;
    d->k = m->n_unknowns;
    d->jac_method = opt->jacobian_method;
    d->is_confirm = nested == 1;
    if (tr_inputs_alloc(m, d) != 0 || alloc_buffers(m, d) != 0 ||
        alloc_integrators(m, d, opt) != 0 || alloc_nodes(m, d, nnode, node_s, nested != 2) != 0)
        goto nomem;
    if (opt->jacobian_method == TR_JAC_HYBRID) {
        d->hyb = gsl_multiroot_fdfsolver_alloc(gsl_multiroot_fdfsolver_hybridsj, (size_t)d->k);
        if (!d->hyb) goto nomem;
    }
    if (nested == 0 && !m->view) {
        const int fine = (flags & TR_ALLOC_FINEST) != 0;
        if ((flags & (TR_ALLOC_GRIDS | TR_ALLOC_FINEST)) && !opt->accept_unstable &&
            (!(d->stab =
                   stab_alloc(d->vm, opt, TR_STAB_ELEMENTS, 0,
                              fine ? TR_STAB_MAX_ELEMENTS : TR_STAB_ELEMENTS, fine ? 6 : 3)) ||
             !(d->stab_quick = stab_alloc(d->vm, opt, TR_STAB_QUICK, 0,
                                          fine ? TR_STAB_MAX_ELEMENTS : TR_STAB_QUICK, 3))))
            goto nomem;
        if ((flags & TR_ALLOC_CALLS) && alloc_calls(m, d) != 0) goto nomem;
        if ((flags & TR_ALLOC_CONFIRM) && opt->continuation &&
            tr_data_alloc_confirm(d->vm, d, msg, msglen) != 0) {
            char why[TR_MSGLEN];
            tr_msgf(why, sizeof why, "%s", msg);
            tr_msgf(msg, msglen, "the confirming formulation could not be set up: %s", why);
            tr_data_free(d);
            return NULL;
        }
    }
    d->probe_bp = -1;
    d->lam_act = d->lam_load = d->lam_hom = d->lam_fric = 1.0;
    d->truncation = NAN;
    d->jacobian_cond = NAN;
    d->residual_norm = NAN;
    return d;
nomem:
    tr_msgf(msg, msglen, "out of memory while allocating the solver workspace");
    tr_data_free(d);
    return NULL;
}

tr_data *tr_data_alloc(const tr_model *m, const tr_options *opt, int nnode, const double *node_s,
                       char *msg, size_t msglen)
{
    return data_alloc(m, opt, nnode, node_s, 0, 0, msg, msglen);
}

tr_data *tr_data_alloc_ext(const tr_model *m, const tr_options *opt, int nnode,
                           const double *node_s, int flags, char *msg, size_t msglen)
{
    return data_alloc(m, opt, nnode, node_s, 0, flags, msg, msglen);
}
