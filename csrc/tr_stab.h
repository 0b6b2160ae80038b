/*
 * tr_stab.h -- the stability test's workspace and the pieces its files share
 * (tr_stab_energy.c: the discretised energy; tr_stability.c: the verdict; tr_switch.c:
 * tendons at their taut/slack switch; tr_data.c: the workspace's allocation).
 */
#ifndef TR_STAB_H
#define TR_STAB_H

#include "tendonrod.h"
#include "tr_internal.h"

/* Uniform elements of the first grid (even), and the most a refinement may use. */
#define TR_STAB_ELEMENTS     24
#define TR_STAB_MAX_ELEMENTS 768
/* Uniform elements of the quick test's grid (even), and the band (times 1 + the
 * stiffness scale) in which it leaves the verdict to the full test: its discretisation
 * error is below 7.6e-3 of that scale on the Euler column from 0.5 to 41 times its load
 * (four times the 24-element figure), so no eigenvalue outside the band can be across
 * zero. */
#define TR_STAB_QUICK      12
#define TR_STAB_QUICK_BAND 0.02
/* The quick test measures the distance of the nearest eigenvalue from zero up to this
 * many bands (by doubling). */
#define TR_STAB_QUICK_GAP 64.0
/* The quick test's a posteriori check (tr_stability.c, verdict_check): a stable solution
 * is decided when its smallest eigenvalue lies beyond this many times the discretisation
 * error estimated from the quick grid and the full test's first grid (the full test
 * calls a margin critical within 2 such errors, and refines it first), and on the quick
 * grid beyond this fraction of the quick band (nearer zero the full test decides). */
#define TR_STAB_POST     8.0
#define TR_STAB_POST_MIN 0.1
/* ... with each grid's smallest eigenvalue bracketed to this fraction of it (the
 * brackets' widths count in the error). */
#define TR_STAB_POST_RTOL 1e-3
/* A margin (scaled by EI/L) within this of zero is round-off: a neutral direction. */
#define TR_STAB_NEUTRAL 1e-7
/* Margins (scaled) smaller than this times (1 + the load-induced stiffness scale) are
 * refined (discrete equilibrium) and checked against the grid of half the elements (the
 * error estimate); larger ones are far beyond the discretisation error (at 24 elements
 * on the Euler column, 0.5 to 41 times its load, below 1e-3 of that scale). */
#define TR_STAB_CHECK 0.05
/* Newton steps to the discrete equilibrium where a margin is refined. */
#define TR_STAB_NEWTON 2

/* The largest element rotation the grid may carry [rad]: keeps the discretisation in
 * its second-order regime (finer grids are built until it holds). */
#define TR_STAB_MAX_ROT 0.35

/* tr_switch.c: tendons at their taut/slack switch. */
/* At most this many tendons at their switch are tested (3^a faces). */
#define TR_SWITCH_MAX 4
/* Eigenvalues within this (times 1 + |lam|) of the smallest form its cluster. */
#define TR_SWITCH_CLUSTER 1e-3
/* A direction is inside a face when each of its tendons' g x has the face's sign by more
 * than this times |g| |x|. */
#define TR_SWITCH_INSIDE 1e-7
/* Inverse-iteration sweeps (the shift sits 1e-4 (1 + |lam|) below the smallest). */
#define TR_SWITCH_SWEEPS 6

/* ------------------------------------------------------------ the workspace */
struct tr_stab_ws {
    int nuni;             /* uniform elements of the fine grid */
    int cap_nuni, cap_nb; /* the finest grid and coordinates per node it has room for */
    int nb, cosserat;     /* coordinates per node; 1: Cosserat elements (else Kirchhoff) */
    int ngrid;            /* nodes of the fine grid: uniform ones and every breakpoint */
    double *s;            /* (ngrid) their arc lengths [m] */
    int *kind;            /* (ngrid) 1: in the coarse grid too (even uniform node or breakpoint) */
    int *node;            /* (ngrid) the grid nodes of the level being assembled */
    tr_data *rec;         /* recording workspace on the grid */
    double *R, *p;        /* (ngrid x 9), (ngrid x 3) the configuration: recorded, then moved
                        to the discrete equilibrium */
    double *tau;          /* (nt) the tensions, idem */
    double *g, *dx;       /* (ngrid nb) gradient of the energy, Newton step */
    double *F, *vhat;     /* (ngrid x 3) per element: the dead force beyond it (Kirchhoff), its
                         free strain (Cosserat), from the recorded state */
    int *col;             /* (nt) bordered column of each tendon, -1: none */
    unsigned long long sw_mask; /* tendons (index < 64) bordered though slack: those at
                                   their switch, for tr_switch.c (0 otherwise) */
    double *sw_buf;             /* (10 x ngrid nb) scratch of tr_switch.c */
    tr_btd h;                   /* the Hessian and its factors */
};

/* tr_data.c: the doubles a grid workspace's blocks hold for cap nodes of nb coordinates
 * and nt tendons (w->R's length), and the grid's arrays laid out in them for cap nodes
 * of w->nb coordinates (w->kind holding 2 cap + nt ints: kinds, nodes, columns), zeroed;
 * the verdict's grids and tr_modes' grids are carved by it. */
size_t tr_stab_len(size_t cap, size_t nb, size_t nt);
void tr_stab_layout(const tr_model *m, struct tr_stab_ws *w, size_t cap);
/* tr_data.c: the workspace *wp set to nuni uniform elements (in place when it has room for
 * them, else reallocated). */
struct tr_stab_ws *tr_stab_workspace(const tr_model *m, tr_data *d, struct tr_stab_ws **wp,
                                     int nuni, int cosserat);
/* tr_stab_energy.c: the level's elements from the recorded state (the grid nodes w->node[0..nn-1]); 0, or
 * -1 when an element turns by more than TR_STAB_MAX_ROT. */
int tr_stab_level_setup(const tr_model *m, const tr_data *d, struct tr_stab_ws *w, int nn);
/* The Hessian (scaled by L/EI), gradient, mass and bordered columns of the level. */
void tr_stab_assemble(const tr_model *m, struct tr_stab_ws *w, int nn, int nb);
/* Newton steps of the level to the discrete equilibrium (reassembled). */
void tr_stab_discrete_equilibrium(const tr_model *m, struct tr_stab_ws *w, int nn, int nb);

/* A stability grid's recording (tr_record_coarse) needs its states to well below the
 * verdict's bands (2 % of the stiffness scale and more), not to the shooting tolerance:
 * RK4 steps of up to this fraction of a shooting step, its tip checked against the
 * shooting tip (redone to the shooting accuracy beyond TR_RECORD_COARSE_TOL). */
#define TR_RECORD_COARSE_FRACTION 0.5
/* ... its tip within this of the shooting tip (scaled states): the verdict's bands leave
 * ~1e-2 (1 + stiffness scale) beyond its discretisation error, which a state error of
 * 1e-5 moves its eigenvalues by orders of magnitude less than; RK4 only where it costs at
 * most half of rk8 (else a redone recording would cost more than it saves). */
#define TR_RECORD_COARSE_TOL 1e-5
/* tr_record.c: the states of a stability grid at the unknowns x (tr_record_from's), by
 * RK4 steps of up to half a shooting step where they cost less than rk8's, accepted when
 * the recorded tip agrees with tip (the shooting end state at x: its n_base base states)
 * to TR_RECORD_COARSE_TOL (scaled), else recorded again to the shooting accuracy; tip NULL:
 * tr_record_from. */
int tr_record_coarse(const tr_model *m, tr_data *d, const double *x, int steps, const double *tip);

/* tr_switch.c: the displacement-controlled tendons at their switch (tension and slack
 * both zero). */
int tr_switch_count(const tr_model *m, const tr_data *d);
/* tr_switch.c: the verdict of a solution whose test on the slack side of its switch
 * tendons found a negative direction (d->stable == 0): the piecewise quadratic energy
 * tested face by face; sets the verdict and its reason. */
void tr_switch_verdict(const tr_model *m, tr_data *d);

#endif
