/*
 * tr_data.c -- the workspace of one solve: everything that changes, allocated
 * once here and freed in tr_data_free.  The solve loop allocates nothing.
 */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <gsl/gsl_errno.h>

#include "tendonrod.h"
#include "tr_internal.h"

void tr_data_free(tr_data *d)
{
    if (!d) return;
    free(d->x);
    free(d->J);
    if (d->LU) gsl_matrix_free(d->LU);
    if (d->perm) gsl_permutation_free(d->perm);
    free(d->tau);
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
    free(d->lin);
    free(d->lin_act);
    free(d->bp_pose);
    if (d->hyb) gsl_multiroot_fdfsolver_free(d->hyb);
    free(d->s);
    free(d);
}

static void dmsg(char *msg, size_t len, const char *fmt, ...)
{
    va_list ap;
    if (!msg || !len) return;
    va_start(ap, fmt);
    vsnprintf(msg, len, fmt, ap);
    va_end(ap);
}

tr_data *tr_data_alloc(const tr_model *m, const tr_options *opt, int nnode, const double *node_s,
                       char *msg, size_t msglen)
{
    tr_data *d;
    int k, nsr, nt, i, nn;
    double *scale = NULL;

    if (msg && msglen) msg[0] = '\0';
    if (!m || !opt) {
        dmsg(msg, msglen, "tr_data_alloc: NULL model or options");
        return NULL;
    }
    if (opt->integrator < TR_RK4 || opt->integrator > TR_ADAPTIVE || opt->steps < 0 ||
        !(opt->tol > 0.0) || !(opt->rtol > 0.0) || opt->max_iter < 0 || opt->max_nfev < 1 ||
        opt->max_continuation < 0 || opt->steps > TR_MAX_STEPS ||
        (opt->jacobian_method < TR_JAC_FD || opt->jacobian_method > TR_JAC_HYBRID) ||
        (opt->slack_model != TR_SLACK_LINEAR && opt->slack_model != TR_SLACK_SQUARED)) {
        dmsg(msg, msglen,
             "invalid solver options (integrator %d, steps %d (max %d), tol %g, rtol %g, "
             "max_iter %d, max_nfev %d, max_continuation %d)",
             opt->integrator, opt->steps, TR_MAX_STEPS, opt->tol, opt->rtol, opt->max_iter,
             opt->max_nfev, opt->max_continuation);
        return NULL;
    }
    if (!node_s && !opt->tip_only && nnode < 2) {
        dmsg(msg, msglen, "nodes = %d must be >= 2 (0 and L)", nnode);
        return NULL;
    }
    if (node_s) {
        if (nnode < 1) {
            dmsg(msg, msglen, "nodes must not be empty");
            return NULL;
        }
        for (i = 0; i < nnode; i++)
            if (!(node_s[i] >= 0.0 && node_s[i] <= m->L * (1.0 + 1e-12)) ||
                (i > 0 && node_s[i] < node_s[i - 1])) {
                dmsg(msg, msglen, "nodes[%d] = %g must be sorted and within [0, L = %g]", i,
                     node_s[i], m->L);
                return NULL;
            }
    }
    d = (tr_data *)calloc(1, sizeof *d);
    if (!d) {
        dmsg(msg, msglen, "out of memory");
        return NULL;
    }
    d->model = m;
    d->opt = *opt;
    k = d->k = m->n_unknowns;
    nsr = m->n_states_rec;
    nt = m->nt;

    d->x = (double *)calloc((size_t)9 * k, sizeof(double));
    d->J = (double *)calloc((size_t)k * k, sizeof(double));
    d->LU = gsl_matrix_alloc(k, k);
    d->perm = gsl_permutation_alloc(k);
    d->tau = (double *)calloc((size_t)(2 * nt + 3 * nt + 1), sizeof(double));
    d->y = (double *)calloc((size_t)8 * nsr, sizeof(double));
    d->Yx = (double *)calloc((size_t)12 * k, sizeof(double));
    d->lin = (double *)calloc((size_t)(2 * m->ndisp * m->ndisp + 3 * m->ndisp + 1), sizeof(double));
    d->lin_act = (int *)calloc((size_t)(2 * m->ndisp + 1), sizeof(int));
    d->bp_pose = (double *)calloc((size_t)12 * (m->nseg + 1), sizeof(double));
    if (!d->bp_pose || !d->lin || !d->lin_act || !d->x || !d->J || !d->LU || !d->perm || !d->tau ||
        !d->y || !d->Yx)
        goto nomem;
    d->f = d->x + k;
    d->xt = d->x + 2 * k;
    d->ft = d->x + 3 * k;
    d->dx = d->x + 4 * k;
    d->xs = d->x + 5 * k;
    d->xp = d->x + 6 * k;
    d->fs = d->x + 7 * k;
    d->work = d->x + 8 * k;
    d->beta = d->tau + nt;
    d->tension = d->tau + 2 * nt;
    d->slack = d->tau + 3 * nt;
    d->displacement = d->tau + 4 * nt;
    d->k1 = d->y + nsr;
    d->k2 = d->y + 2 * nsr;
    d->k3 = d->y + 3 * nsr;
    d->k4 = d->y + 4 * nsr;
    d->yt = d->y + 5 * nsr;
    d->yerr = d->y + 6 * nsr;
    d->ysave = d->y + 7 * nsr;
    d->Fp = d->Yx + 6 * k;

    if (opt->jacobian_method == TR_JAC_HYBRID) {
        d->hyb = gsl_multiroot_fdfsolver_alloc(gsl_multiroot_fdfsolver_hybridsj, (size_t)k);
        if (!d->hyb) goto nomem;
    }
    /* ODE systems and steppers (both layouts) */
    d->sys_shoot.function = tr_rhs;
    d->sys_shoot.jacobian = NULL;
    d->sys_shoot.dimension = (size_t)m->n_states;
    d->sys_shoot.params = d;
    d->sys_rec = d->sys_shoot;
    d->sys_rec.dimension = (size_t)nsr;
    d->rk8_shoot = gsl_odeiv2_step_alloc(gsl_odeiv2_step_rk8pd, m->n_states);
    d->rk8_rec = gsl_odeiv2_step_alloc(gsl_odeiv2_step_rk8pd, nsr);
    if (!d->rk8_shoot || !d->rk8_rec) goto nomem;
    if (opt->integrator == TR_ADAPTIVE) {
        scale = (double *)malloc((size_t)nsr * sizeof(double));
        if (!scale) goto nomem;
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
        scale = NULL;
        if (!d->ad_step_shoot || !d->ad_step_rec || !d->ad_ctl_shoot || !d->ad_ctl_rec ||
            !d->ad_ev_shoot || !d->ad_ev_rec)
            goto nomem;
    }

    /* output nodes */
    if (opt->tip_only) {
        nn = 1;
    } else if (node_s) {
        nn = nnode;
    } else {
        nn = nnode + 2 * (m->nseg - 1); /* upper bound; the merge sets the count */
    }
    d->nnode = nn;
    d->s = (double *)calloc((size_t)nn * 19, sizeof(double));
    if (!d->s) goto nomem;
    d->pos = d->s + nn;
    d->rot = d->s + 4 * nn;
    d->force = d->s + 13 * nn;
    d->moment = d->s + 16 * nn;
    if (opt->tip_only) {
        d->s[0] = m->L;
    } else if (node_s) {
        for (i = 0; i < nn; i++) d->s[i] = node_s[i] > m->L ? m->L : node_s[i];
    } else {
        /* merge the uniform grid with each interior breakpoint: twice where a load or
         * an anchor makes a jump (before and after it), once at a shooting node */

        int iu = 0, ib = 1, o = 0;
        while ((iu < nnode || ib < m->nseg) && o < nn) {
            const double su = iu < nnode
                                  ? (iu == nnode - 1 ? m->L : m->L * ((double)iu / (nnode - 1)))
                                  : INFINITY;
            const double sb = ib < m->nseg ? m->bp[ib] : INFINITY;
            if (ib < m->nseg && sb <= su && o + 2 <= nn) {
                d->s[o++] = sb;
                if (m->bp_jump[ib]) d->s[o++] = sb;
                ib++;
                if (fabs(su - sb) <= 1e-12 * m->L) iu++;
            } else if (iu < nnode) {
                d->s[o++] = su;
                iu++;
            } else {
                break;
            }
        }
        d->nnode = nn = o;
    }
    d->probe_bp = -1;
    d->lam_act = d->lam_load = 1.0;
    d->truncation = NAN;
    d->jacobian_cond = NAN;
    d->residual_norm = NAN;
    return d;
nomem:
    free(scale);
    dmsg(msg, msglen, "out of memory while allocating the solver workspace");
    tr_data_free(d);
    return NULL;
}
