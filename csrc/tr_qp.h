/*
 * tr_qp.h -- a small dense convex quadratic program, the step of the inverse actuation's
 * outer iteration (tendonrod.actuate):
 *
 *     minimise   1/2 u^T H u + g^T u
 *     subject to A u = b,  G u >= h
 *
 * with H symmetric positive definite, a handful of unknowns and a few dozen constraints.
 */
#ifndef TR_QP_H
#define TR_QP_H

#include <stddef.h>

/* Largest sizes accepted: the actuated tendons and a few constraints per tendon. */
#define TR_QP_MAX_N    256
#define TR_QP_MAX_ROWS 4096

#ifdef __cplusplus
extern "C" {
#endif

/* Doubles of workspace tr_qp needs for n unknowns, me equalities and mi inequalities. */
size_t tr_qp_work_len(int n, int me, int mi);

/* The primal active-set method (Nocedal and Wright, Numerical Optimization, algorithm
 * 16.3) from x0 (n), which satisfies the equalities A x0 = b (b itself is not needed): a
 * constraint x0 violates is relaxed to what x0 satisfies.  Each subproblem is the
 * equality-constrained minimiser on the working set, found in the null space of its
 * constraints (by SVD, rank to 1e-12 of the largest singular value); a blocking
 * constraint joins the working set (the lowest-numbered of ties), one with a negative
 * multiplier leaves it (Bland's rule: the lowest-numbered), at most max_iter times.
 * Row-major inputs: H (n x n), g (n), A (me x n), G (mi x n), h (mi).  Outputs: u (n) the
 * minimiser; lam (me) and mu (mi) the multipliers (H u + g = A^T lam + G^T mu, mu >= 0,
 * zero off the working set); active (mi) flags of the inequalities that hold with
 * equality at u (to 1e-12 of the problem's scale).  work: tr_qp_work_len doubles.
 * Returns the number of active inequalities, TR_EINVAL for sizes out of range, or
 * TR_ESINGULAR when a reduced Hessian Z^T H Z is singular (H not positive definite on
 * the working set's null space). */
int tr_qp(int n, const double *H, const double *g, int me, const double *A, int mi, const double *G,
          const double *h, const double *x0, int max_iter, double *u, double *lam, double *mu,
          int *active, double *work);

/* Doubles of workspace tr_lstsq needs for an (r x c) matrix. */
size_t tr_lstsq_work_len(int r, int c);

/* The least-norm least-squares solution x of E x = b, E = M (r x c, row-major) or, with
 * trans, its transpose M^T: x (c, or r with trans), b (r, or c).  By the one-sided Jacobi
 * SVD of the taller of E and E^T; singular values below rcond times the largest are
 * dropped (NumPy's lstsq with that rcond).  work: tr_lstsq_work_len(r, c) doubles.
 * Returns 0, or -1 when the SVD fails. */
int tr_lstsq(int r, int c, const double *M, int trans, const double *b, double rcond, double *x,
             double *work);

/* The Gauss-Newton model of 1/2 |r + A u|^2 (A m x n, row-major): H (n x n) = A^T A,
 * regularised by 1e-12 of its mean diagonal, and g (n) = A^T r. */
void tr_gauss_newton(int n, int m, const double *A, const double *r, double *H, double *g);

/* The first-order test of a least-squares point of |r + A u| at u = 0 under bounds G u >= h
 * (G mi x n, each row one nonzero; a row with h >= 0 is active at u = 0 and blocks the
 * descent -a_j^T r of its control where the two point against each other): max_j |a_j^T r| /
 * (|a_j| |r|) over the controls not blocked (MINPACK's gtol cosine; 0 for a control whose
 * column a_j is zero). */
double tr_lsq_cosine(int n, int m, const double *A, const double *r, int mi, const double *G,
                     const double *h);

/* Powell's damped BFGS update of H (n x n) for the step s and the change y of the
 * gradient (y is damped in place; Hs: n doubles of scratch, H s on return): the curvature
 * the plain least change (H = I) leaves out, so that the iteration converges
 * superlinearly. */
void tr_bfgs_update(int n, double *H, const double *s, double *y, double *Hs);

#ifdef __cplusplus
}
#endif
#endif /* TR_QP_H */
