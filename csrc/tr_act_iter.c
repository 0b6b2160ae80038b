/*
 * tr_act_iter.c -- the iterate of an inverse actuation (tr_act_iter.h): its buffers, its
 * moves between the run's states (tr_act_run.c), the slack taken up before a
 * linearisation, the sides of the taut/slack switch its derivatives are taken on, and the
 * tension floors of the current state.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "tr_act_iter.h"
#include "tr_internal.h"
#include "tr_qp.h"
#include "tru_math.h"

/* Move to state s at controls c (copied). */
void tr_act_set_state(act_iter *it, const double *c, int s)
{
    if (c != it->c) memcpy(it->c, c, (size_t)it->n * sizeof(double));
    it->a->cur = s;
    it->lin = it->rows_ok = 0;
    it->nslack_side = 0;
    /* within 1e4 tol of the target, iterate solves are polished (see tr_act_run.c) */
    it->a->polish = tru_maxnorm(it->a->pool[s].r, it->mt) <= 1e4 * it->sp->tol;
}

/* The guess (6 + 2 nt) of the equilibrium at controls cn that differ from the current ones
 * only in slack displacement controls: the same equilibrium (a slack tendon moves
 * nothing), those tendons' slack changed by the length paid out, c - cn. */
const double *tr_act_slack_state(act_iter *it, const double *cn)
{
    const act_state *st = tr_act_cur(it);
    const int nt = it->nt;
    int j;
    memcpy(it->gbuf, st->g, (size_t)(6 + 2 * nt) * sizeof(double));
    for (j = 0; j < it->n; j++)
        if (cn[j] != it->c[j]) {
            const int i = it->sp->idx[j];
            it->gbuf[6 + i] = 0.0;
            it->gbuf[6 + nt + i] = fmax(st->slack[i] + (it->c[j] - cn[j]), 0.0);
        }
    return it->gbuf;
}

/* Slack displacement controls moved to the taut side of their switch, their slack taken
 * up (a hair past it, 1e-12 of the scale), where the linearisation sees them act (on the
 * slack side pulling one moves nothing, and the iteration would never pull it back): in
 * least squares every slack one; in the least change those held taut (a finite floor,
 * which then keeps them there), and those below their scene value, drawn toward it (up to
 * the switch at most: a pull the least change gets for free).  A slack tendon moves
 * nothing, so the target residual stays where it was. */
static void to_taut_side(act_iter *it)
{
    const tr_act_spec *sp = it->sp;
    const act_state *st = tr_act_cur(it);
    double *cn = it->cn;
    int j, s;
    memcpy(cn, it->c, (size_t)it->n * sizeof(double));
    for (j = 0; j < it->n; j++) {
        const int i = sp->idx[j];
        const double slack = st->slack[i];
        if (!(it->disp[i] && slack > 0.0)) continue;
        if (it->lsq || isfinite(sp->floor0[i]))
            cn[j] += slack + 1e-12 * sp->scale[j];
        else if (sp->c0[j] > it->c[j])
            cn[j] = fmin(it->c[j] + slack + 1e-12 * sp->scale[j], sp->c0[j]);
    }
    if (tr_act_equal(cn, it->c, it->n)) return;
    s = tr_act_solve(it->a, cn, tr_act_slack_state(it, cn));
    if (s < 0) {
        tr_act_solve(it->a, it->c, NULL); /* the workspace's warm state back at c */
        return;
    }
    tr_act_set_state(it, cn, s);
}

/* The side of its switch whose derivatives each tendon at it is to get: the taut one for
 * the displacement controls of least squares, those the least change holds taut (their
 * steps keep them there) and those it would pull toward their scene value (pulling acts
 * through the taut side); the side it is on for the others. */
static void wanted_sides(act_iter *it)
{
    const tr_act_spec *sp = it->sp;
    int j;
    memset(it->side, 0, (size_t)it->nt * sizeof(double));
    for (j = 0; j < it->n; j++) {
        const int i = sp->idx[j], pull = sp->c0[j] > it->c[j] && !it->lsq;
        if (it->disp[i] && (it->lsq || isfinite(sp->floor0[i]) || pull)) it->side[i] = 1.0;
    }
    for (j = 0; j < it->nslack_side; j++) it->side[it->slack_side[j]] = -1.0;
}

/* The linearisation at the current state, computed on first use (a state that meets the
 * target in a square or least-squares problem needs none): 0, or -1 (it->err set). */
int tr_act_linearisation(act_iter *it)
{
    int status;
    if (it->lin) return 0;
    to_taut_side(it);
    wanted_sides(it);
    status = tr_act_linearize(it->a, it->a->cur, it->side, it->A, it->T, it->sw);
    if (status != TR_OK) {
        it->err = status;
        return -1;
    }
    it->lin = 1;
    return 0;
}

/* Lower bounds on the signed tensions (nt) [N]: the scene's taut tendons' (min_tension),
 * and 0 for the displacement controls taut or at the taut side of their switch now (the
 * least change puts one that would rather be slack exactly at its switch, where it stops
 * costing).  0, or -1 (a linearisation failed). */
int tr_act_floors(act_iter *it, double *f)
{
    const tr_act_spec *sp = it->sp;
    int j, need = 0;
    memcpy(f, sp->floor0, (size_t)it->nt * sizeof(double));
    for (j = 0; j < it->n; j++)
        need |= it->disp[sp->idx[j]] && !(tr_act_cur(it)->tension[sp->idx[j]] > 0.0);
    if (need && tr_act_linearisation(it) < 0) return -1;
    for (j = 0; j < it->n; j++) {
        const int i = sp->idx[j];
        const int held = tr_act_cur(it)->tension[i] > 0.0 || (need && it->sw[i] > 0);
        if (it->disp[i] && held) f[i] = fmax(f[i], 0.0);
    }
    return 0;
}

int tr_act_iter_alloc(act_iter *it, act_run *a, const tr_act_spec *sp)
{
    const size_t n = (size_t)sp->n, nt = (size_t)a->nt, mt = (size_t)sp->target.m;
    const size_t gmax = nt + 5 * n + 1, qpw = tr_qp_work_len(sp->n, sp->target.m, (int)gmax);
    /* every buffer and its length: one block of doubles, one of ints */
    struct {
        double **p;
        size_t len;
    } dv[] = {{&it->c, n},
              {&it->cn, n},
              {&it->c2, n},
              {&it->ca, n},
              {&it->u, n},
              {&it->v, n},
              {&it->dd, n},
              {&it->u0, n},
              {&it->gold, n},
              {&it->gnew, n},
              {&it->s, n},
              {&it->y, n},
              {&it->Hs, n},
              {&it->g0, n},
              {&it->qg, n},
              {&it->H, n * n},
              {&it->QH, n * n},
              {&it->A, mt * n},
              {&it->T, nt * n},
              {&it->Gfix, 3 * n * n},
              {&it->hfix, n},
              {&it->G, gmax * n},
              {&it->h, gmax},
              {&it->mu, gmax},
              {&it->M, (mt + nt) * n},
              {&it->rhs, mt + nt},
              {&it->mus, nt},
              {&it->floor, nt},
              {&it->psi, nt},
              {&it->psin, nt},
              {&it->side, nt},
              {&it->gbuf, 6 + 2 * nt},
              {&it->qpw, qpw}};
    struct {
        int **p;
        size_t len;
    } iv[] = {{&it->sw, nt},   {&it->slack_side, nt}, {&it->disp, nt},
              {&it->rows, nt}, {&it->keep, nt + n},   {&it->active, gmax}};
    const size_t nd = sizeof dv / sizeof dv[0], ni = sizeof iv / sizeof iv[0];
    size_t len = 0, ilen = 0, j;
    double *w;
    int *iw, i;
    memset(it, 0, sizeof *it);
    it->a = a, it->sp = sp, it->n = (int)n, it->nt = (int)nt, it->mt = (int)mt;
    for (j = 0; j < nd; j++) len += dv[j].len;
    for (j = 0; j < ni; j++) ilen += iv[j].len;
    it->wblock = w = (double *)tr_data_take(a->d, len * sizeof(double));
    it->iblock = iw = (int *)tr_data_take(a->d, ilen * sizeof(int));
    if (!w || !iw) {
        tr_act_iter_free(it);
        return -1;
    }
    for (j = 0; j < nd; j++) *dv[j].p = w, w += dv[j].len;
    for (j = 0; j < ni; j++) *iv[j].p = iw, iw += iv[j].len;
    for (i = 0; i < (int)nt; i++) it->disp[i] = a->m->tendon[i].control == TR_DISPLACEMENT;
    for (i = 0; i < (int)n; i++) it->H[i * (int)n + i] = 1.0;
    it->delta = TR_ACT_DELTA0;
    it->lsq = sp->kind != TR_ACT_MIN_CHANGE;
    it->gcos = NAN;
    it->gcos_at = -1;
    return 0;
}

void tr_act_iter_free(act_iter *it)
{
    tr_data_drop(it->a->d, it->iblock);
    tr_data_drop(it->a->d, it->wblock);
    it->iblock = NULL;
    it->wblock = NULL;
}
