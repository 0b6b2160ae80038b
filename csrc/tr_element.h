/*
 * tr_element.h -- the energy of one element of the discretised rod and its tendons, in
 * hyper-dual arithmetic (tr_hd.h), for the stability test (tr_stability.c).
 */
#ifndef TR_ELEMENT_H
#define TR_ELEMENT_H

#include "tendonrod.h"
#include "tr_hd.h"
#include "tr_internal.h"

/* coordinates per node: rotation (3), position (3) if Cosserat */
#define TR_ELEM_NB TR_BTD_MAXB

typedef struct {
    const tr_model *m;
    int cosserat;
    double h, sa, sb;      /* element length, arc lengths of its nodes [m] */
    const double *Ra, *Rb; /* (9) rotations of its nodes, body-to-world, row-major */
    const double *pa, *pb; /* (3) positions [m] */
    double F[3];           /* Kirchhoff: dead force beyond the element, world [N] */
    double vhat[3];        /* Cosserat: the strain at which the element's shear and
                                 extension are free, set so that its internal force at the
                                 recorded state is the solution's (see assemble) */
    const double *tau;     /* (nt) tensions [N] */
    int seg;               /* the integration segment holding the element */
    const double *sr;      /* its rigidities and precurvature (TR_SR_NCOL: m->seg_rod's row,
                              or m->rod_k on a uniform straight rod) */
} tr_elem;

/* Energy of element e as a function of the perturbations xa, xb (nb each) of its nodes
 * (body-frame rotation vectors, then positions on a Cosserat element); only == -1: the
 * whole energy, only >= 0: the length of tendon only's chord. */
tr_hd tr_elem_energy(const tr_elem *e, const tr_hd *xa, const tr_hd *xb, int only);
/* The whole energy of element e with its gradient g (2 nb) and Hessian H (2 nb x 2 nb,
 * row-major) in the perturbations of node a's nb coordinates, then node b's: 21 hyper-dual
 * passes on a Kirchhoff element, 45 on a Cosserat one (its positions enter only through
 * the chord p_b - p_a), 21 when node a is clamped (clamped_a: its rows are left zero). */
double tr_elem_hessian(const tr_elem *e, int nb, int clamped_a, double *g, double *H);
/* A Kirchhoff element (nb = 3) of a model with at most TR_ELEM_CHORDS tendons:
 * tr_elem_hessian's g and H, and in gc (nt x 6) the gradient of each tendon's chord
 * length as tr_elem_chord_gradient's, from the same passes (zero for a tendon that ends
 * before the element). */
#define TR_ELEM_CHORDS 16
double tr_elem_hessian_chords(const tr_elem *e, int clamped_a, double *g, double *H, double *gc);
/* The gradient g (2 nb, as tr_elem_hessian's) of the length of tendon i's chord on
 * element e, one first-order hyper-dual pass per variable. */
void tr_elem_chord_gradient(const tr_elem *e, int nb, int clamped_a, int i, double *g);
/* Cosserat: the strain v = Rm^T (p_b - p_a) / h of element e (Rm its midpoint frame). */
void tr_elem_strain(const tr_elem *e, const tr_hd *xa, const tr_hd *xb, tr_hd *v);
/* Rm^T x at the recorded state (no perturbation), x world. */
void tr_elem_midframe_t(const tr_elem *e, const double *x, double *out);

#endif /* TR_ELEMENT_H */
