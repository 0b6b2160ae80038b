/*
 * tr_modes.h -- natural frequencies and mode shapes of small vibrations about a solved
 * equilibrium (tr_modes.c): the stiffness is the second variation of the energy that the
 * stability verdict assembles (tr_stab_energy.c, on Cosserat elements), the mass is
 * lumped at the nodes (the rod's rho A and rotary inertia, point masses); the pencil's
 * lowest eigenvalues by shift-invert subspace iteration on the block LDL^T of the
 * verdict (tr_inertia.c), checked by its Sturm count, on two or three grids of halved
 * elements and extrapolated (Richardson: the elements and the lumped mass are second
 * order in the element length).
 */
#ifndef TR_MODES_H
#define TR_MODES_H

#include "tendonrod.h"

/* Elements of the coarsest grid (spread over the segments between breakpoints in
 * proportion to their lengths, at least one each) and the grids (each halves the
 * elements of the one before): the default and the limits. */
#define TR_MODES_ELEMENTS     24
#define TR_MODES_MAX_ELEMENTS 4096
#define TR_MODES_LEVELS       3
#define TR_MODES_MAX_LEVELS   5
/* The most modes asked for at once. */
#define TR_MODES_MAX 64
/* A Kirchhoff rod is unshearable and inextensible; its elements get the shear and axial
 * rigidity TR_MODES_PENALTY EI / h^2 (h the grid's nominal element length L / N): an
 * error of order h^2 (the shear deflection of a beam is 3 (EI / GA L^2) = 3 h^2 /
 * (penalty L^2) of its bending one) that the extrapolation removes with the elements'
 * own, while the element's stiffest vibration stays of the order of its bending one
 * (the pencil's conditioning, ~N^4, is the Kirchhoff discretisation's own). */
#define TR_MODES_PENALTY 50.0
/* Subspace iteration: extra vectors beyond the n asked for, the most sweeps, and the
 * relative change of the n Ritz values at which a grid's iteration stops. */
#define TR_MODES_GUARD    8
#define TR_MODES_SWEEPS   300
#define TR_MODES_RITZ_TOL 1e-13
/* The Sturm check of a grid's n Ritz values: no eigenvalue of the pencil is missed below
 * (1 - TR_MODES_STURM) lambda_n. */
#define TR_MODES_STURM 1e-7
/* ... or below it by this many times the round-off (eps times Gershgorin's bound on the
 * largest eigenvalue), where that is larger: a fine grid's count does not resolve its
 * n-th eigenvalue better. */
#define TR_MODES_STURM_ROUNDOFF 10.0
/* The extrapolation is trusted where the ratio of successive grid differences is within
 * [4 - TR_MODES_RATIO_BAND, 4 + TR_MODES_RATIO_BAND] (second order: 4); elsewhere the
 * accuracy estimate is the finest grid's difference itself. */
#define TR_MODES_RATIO_BAND 1.0

/* The round-off of a grid's eigenvalues: this many times eps times Gershgorin's bound on
 * its largest (the solves' residuals are eps |H| |x|; measured: the lowest cantilever
 * eigenvalue's round-off at 96 to 192 elements is 0.01 to 0.19 of eps times the bound). */
#define TR_MODES_ROUNDOFF 0.3
/* A mode whose centre line moves by less than this times L |dtheta| (pure torsion) is
 * normalised by its rotation. */
#define TR_MODES_TWIST 1e-6

/* What the caller gives: the mass and the discretisation. */
typedef struct {
    int n;     /* modes asked for (1..TR_MODES_MAX) */
    int nmass; /* rows of mass: (nmass x 5) [s_end, rho A [kg/m], rho I1, rho I2,
                          rho J [kg m]] per section, base first, the last s_end = L */
    const double *mass;
    int npm; /* point masses: (npm x 2) [s [m], mass [kg]] on the centre line */
    const double *pm;
    int elements; /* elements of the coarsest grid (0: TR_MODES_ELEMENTS) */
    int levels;   /* grids (1..TR_MODES_MAX_LEVELS; 0: TR_MODES_LEVELS) */
    int rotary;   /* 1: the rotary inertia of the section (0: none, Euler-Bernoulli) */
} tr_modes_spec;

/* What it returns (allocated by tr_modes after the computation, one block: released by
 * tr_modes_out_free). */
typedef struct {
    int n, nlev;        /* modes; grids */
    double *omega2;     /* (n) eigenvalues omega^2 [rad^2/s^2], extrapolated, ascending */
    double *error;      /* (n) their accuracy estimate (absolute, [rad^2/s^2]) */
    double *levels;     /* (levels x n) the eigenvalue of each grid, coarse first */
    double *modal_mass; /* (n) x^T M x of the normalised shapes [kg] */
    double *s;          /* (ns) arc lengths of the shape samples [m] */
    double *pos0;       /* (ns x 3) the equilibrium's positions there [m], world */
    double *dpos;       /* (n x ns x 3) shape displacements, world, normalised */
    double *drot;       /* (n x ns x 3) shape rotations, world rotation vectors */
    int ns, nit, nfac;  /* samples; subspace sweeps; factorisations (Sturm counts included) */
    char message[256];
} tr_modes_out;

/* The modes of the solution x (steps integration steps) of m with workspace d (its poll
 * hook is honoured).  TR_OK, or < 0 with out->message: TR_EINVAL (bad spec),
 * TR_ENOMEM, TR_EINTERRUPTED / TR_EBUDGET (the poll), TR_ESINGULAR... (see the source). */
int tr_modes(const tr_model *m, tr_data *d, const double *x, int steps, const tr_modes_spec *spec,
             tr_modes_out *out);
void tr_modes_out_free(tr_modes_out *out);

#endif /* TR_MODES_H */
