/*
 * tr_closed.c -- external definitions of the closed-form kernels of
 * tr_closed.h (paper Sections II-III).
 *
 * The kernels are C99 inline functions defined in the header, so the NumPy
 * ufunc loops in tendonrod/_ufuncs.c can inline them.  C99 (6.7.4) requires one
 * translation unit to provide the external definition of each inline
 * function for callers that do not inline it; these `extern` declarations of
 * the inline definitions emit exactly that.  All formulas, units, domains
 * and limits are documented in tr_closed.h.
 */
#include "tr_closed.h"

extern inline int tr_closed_beam_ok(double L, double EI);
extern inline double tr_closed_tension(double F, double z, double L, double EI, double a, double b,
                                       double k);
extern inline double tr_closed_angle_tau(double s, double F, double z, double L, double EI,
                                         double a, double b, double tau);
extern inline double tr_closed_deflection_tau(double s, double F, double z, double L, double EI,
                                              double a, double b, double tau);
extern inline double tr_closed_angle(double s, double F, double z, double L, double EI, double a,
                                     double b, double k);
extern inline double tr_closed_deflection(double s, double F, double z, double L, double EI,
                                          double a, double b, double k);
extern inline double tr_closed_equivalent_stiffness(double k, double k_B);
extern inline double tr_closed_pattern_factor(double n);
extern inline double tr_closed_actuation_tension_for_angle(double theta_L, double L, double EI,
                                                           double a, double b);
extern inline double tr_closed_actuation_tension_for_deflection(double delta_L, double L, double EI,
                                                                double a, double b);
