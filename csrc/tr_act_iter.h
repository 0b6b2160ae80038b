/*
 * tr_act_iter.h -- the iterate of an inverse actuation (tr_actuate.c): its controls, the
 * state of the run it stands at, that state's linearisation, the trust region and the
 * step's scratch; its moves between states (tr_act_iter.c).  Internal to the core.
 */
#ifndef TR_ACT_ITER_H
#define TR_ACT_ITER_H

#include "tr_act_run.h"

/* A step's outcome when a linearisation or the step's QP failed (it->err says which). */
enum { ACT_ERROR = -1 };

typedef struct {
    act_run *a;
    const tr_act_spec *sp;
    int n, nt, mt, lsq, err;
    int *disp;         /* (nt) 1: displacement-controlled */
    double *c;         /* (n) the current controls (the state is a->cur) */
    int lin;           /* 1: A, T, sw are the current state's linearisation */
    double *A, *T;     /* (mt x n), (nt x n) */
    int *sw;           /* (nt) the sides of their switch the tendons' derivatives are from */
    double *side;      /* (nt) the sides asked for */
    int nslack_side;   /* tendons at their switch linearised on the slack side */
    int *slack_side;   /* (nt) */
    int rows_ok, nfix; /* the trust region's fixed rows at this state (nfix of them) */
    double *Gfix, *hfix;
    double *H;    /* (n x n) quasi-Newton Hessian of the Lagrangian (minimum change) */
    double nu;    /* the merit's penalty on the target and tension floors */
    double delta; /* trust region (scaled controls) */
    int rejected, optimal, have_lam;
    double gcos;   /* square, least squares: the optimality test's cosine at state gcos_at */
    int gcos_at;   /* (the slot; -1: none) */
    double lam[6]; /* the target's multipliers */
    double *mus;   /* (nt) the tension floors' multipliers */
    /* scratch */
    double *cn, *c2, *ca, *u, *v, *dd, *u0, *gold, *gnew, *s, *y, *Hs, *g0, *qg;
    double *QH, *G, *h, *mu, *M, *rhs, *floor, *psi, *psin, *gbuf, *qpw;
    int *active, *rows, *keep;
    double *wblock; /* the block of doubles and the block of ints the buffers are in */
    int *iblock;
} act_iter;

/* The state the iterate stands at. */
static inline const act_state *tr_act_cur(const act_iter *it)
{
    return it->a->pool + it->a->cur;
}

static inline double tr_act_dot(const double *x, const double *y, int n)
{
    double s = 0.0;
    int i;
    for (i = 0; i < n; i++) s += x[i] * y[i];
    return s;
}

/* 1: x and y (n each) are equal element by element. */
static inline int tr_act_equal(const double *x, const double *y, int n)
{
    int i;
    for (i = 0; i < n; i++)
        if (!(x[i] == y[i])) return 0;
    return 1;
}

/* Every buffer of the iterate at the run a and spec sp, in one block of doubles and one of
 * ints, with its first trust region and Hessian: 0, or -1 (out of memory). */
int tr_act_iter_alloc(act_iter *it, act_run *a, const tr_act_spec *sp);
void tr_act_iter_free(act_iter *it);
/* Move to state s at controls c (copied). */
void tr_act_set_state(act_iter *it, const double *c, int s);
/* The guess of the equilibrium at controls cn that differ from the current ones only in
 * slack displacement controls (in it->gbuf). */
const double *tr_act_slack_state(act_iter *it, const double *cn);
/* The linearisation at the current state, computed on first use: 0, or -1 (it->err). */
int tr_act_linearisation(act_iter *it);
/* Lower bounds on the signed tensions (nt) [N] at the current state: 0, or -1. */
int tr_act_floors(act_iter *it, double *f);

#endif
