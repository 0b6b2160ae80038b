/*
 * tr_internal.h -- functions shared between the core's translation units
 * (not part of the public API).
 */
#ifndef TR_INTERNAL_H
#define TR_INTERNAL_H

#include "tendonrod.h"

/* State layouts (MODEL.md): spatial p (3), R (9, row-major), n_b (3), m_b (3),
 * then path lengths; planar x, z, theta, n_b1, n_b3, m_b2, then path lengths. */
enum { TR_Y_P = 0, TR_Y_R = 3, TR_Y_N = 12, TR_Y_M = 15, TR_Y_LEN = 18 };
enum {
    TR_YP_X = 0,
    TR_YP_Z = 1,
    TR_YP_TH = 2,
    TR_YP_N1 = 3,
    TR_YP_N3 = 4,
    TR_YP_M = 5,
    TR_YP_LEN = 6
};

/* tr_rod.c */
int tr_rhs(double s, const double y[], double dyds[], void *params);
/* Unit tangent of tendon i at s (body frame) and its offset r (body frame), for the
 * state y (either layout). */
void tr_tendon_tangent(const tr_model *m, int i, double s, const double *y, double that[3],
                       double r[3]);
/* Tendon pulls across a section (see tr_rod.c). */
void tr_section_pulls(const tr_model *m, const tr_data *d, int seg, double s, const double nb[3],
                      const double mb[3], double fn[3], double fm[3], double *J6);
/* Pose (p (3), R (9)), internal force and moment (world) of a state y. */
void tr_state_world(const tr_model *m, const double *y, double p[3], double R[9], double n[3],
                    double mom[3]);

/* tr_integrate.c: integrate y over [s0, s1] on segment d->seg (layout d->rec). */
int tr_integrate(const tr_model *m, tr_data *d, double s0, double s1, int nsteps, double *y);
int tr_segment_steps(const tr_model *m, const tr_data *d, int seg);

/* tr_shoot.c */
void tr_set_message(tr_data *d, const char *fmt, ...);

#endif
