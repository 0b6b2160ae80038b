/*
 * tr_inertia.c -- the inertia of a symmetric block-tridiagonal matrix with a border,
 * for the stability verdict (tr_stability.c).
 *
 * A = H - lam M, H with nblk diagonal blocks D_j and couplings E_j (block j to j + 1),
 * M diagonal; bordered by the columns B with compliances C: the number of eigenvalues
 * of the pencil (H, M) below lam on {x : B^T x = C mu, ...} follows from the block
 * LDL^T of A (a Sturm sequence: the inertia of the pivots, Cholesky where a pivot is
 * positive definite, eigenvalues where not) and Haynsworth's additivity:
 * In([[A, B], [B^T, -C]]) = In(A) + In(-C - B^T A^-1 B), less one negative per column.
 */
#include <math.h>
#include <string.h>

#include "tendonrod.h"
#include "tr_internal.h"

/* ------------------------------------------------------------ small symmetric eigen */
/* Eigenvalues of the n x n symmetric A (destroyed) into ev, eigenvectors as the columns
 * of V (row-major), by cyclic Jacobi rotations (n <= TR_STAB_MAXB). */
static void sym_eig(int n, double *A, double *ev, double *V)
{
    int i, j, p, q, sweep;
    for (i = 0; i < n * n; i++) V[i] = (i / n == i % n);
    for (sweep = 0; sweep < 50; sweep++) {
        double off = 0.0, diag = 0.0;
        for (p = 0; p < n; p++) {
            diag += A[p * n + p] * A[p * n + p];
            for (q = p + 1; q < n; q++) off += A[p * n + q] * A[p * n + q];
        }
        if (!(off > 1e-30 * diag)) break;
        for (p = 0; p < n; p++)
            for (q = p + 1; q < n; q++) {
                const double apq = A[p * n + q];
                double t, c, s, theta;
                if (apq == 0.0) continue;
                theta = (A[q * n + q] - A[p * n + p]) / (2.0 * apq);
                t = (theta >= 0 ? 1.0 : -1.0) / (fabs(theta) + sqrt(theta * theta + 1.0));
                c = 1.0 / sqrt(t * t + 1.0);
                s = t * c;
                for (j = 0; j < n; j++) {
                    const double ap = A[p * n + j], aq = A[q * n + j];
                    A[p * n + j] = c * ap - s * aq;
                    A[q * n + j] = s * ap + c * aq;
                }
                for (j = 0; j < n; j++) {
                    const double ap = A[j * n + p], aq = A[j * n + q];
                    A[j * n + p] = c * ap - s * aq;
                    A[j * n + q] = s * ap + c * aq;
                }
                for (j = 0; j < n; j++) {
                    const double vp = V[j * n + p], vq = V[j * n + q];
                    V[j * n + p] = c * vp - s * vq;
                    V[j * n + q] = s * vp + c * vq;
                }
            }
    }
    for (i = 0; i < n; i++) ev[i] = A[i * n + i];
}

/* Cholesky factor of the n x n symmetric A into Lf (lower, row-major); 0 when A is not
 * (numerically) positive definite. */
static int chol(int n, const double *A, double *Lf)
{
    int i, j, k;
    double dmax = 0.0;
    for (i = 0; i < n; i++) dmax = fmax(dmax, fabs(A[i * n + i]));
    for (i = 0; i < n; i++)
        for (j = 0; j <= i; j++) {
            double acc = A[i * n + j];
            for (k = 0; k < j; k++) acc -= Lf[i * n + k] * Lf[j * n + k];
            if (i == j) {
                if (!(acc > 1e-12 * dmax)) return 0;
                Lf[i * n + i] = sqrt(acc);
            } else {
                Lf[i * n + j] = acc / Lf[j * n + j];
            }
        }
    return 1;
}

/* b = A^-1 b from the Cholesky factor Lf */
static void chol_solve(int n, const double *Lf, double *b)
{
    int i, k;
    for (i = 0; i < n; i++) {
        double acc = b[i];
        for (k = 0; k < i; k++) acc -= Lf[i * n + k] * b[k];
        b[i] = acc / Lf[i * n + i];
    }
    for (i = n - 1; i >= 0; i--) {
        double acc = b[i];
        for (k = i + 1; k < n; k++) acc -= Lf[k * n + i] * b[k];
        b[i] = acc / Lf[i * n + i];
    }
}

/* X = A^-1 X (n x ncol, row-major) with the factors of the last tr_btd_count (which
 * must have found no singular pivot): L y = x, D z = y, L^T x = z for the block
 * LDL^T with L_{j+1,j} = U_j^T. */
void tr_btd_solve(tr_btd *w, double *X, int ncol)
{
    const int nblk = w->nblk, nb = w->nb, nb2 = nb * nb;
    int j, r, c, q;
    /* forward: y_{j+1} = x_{j+1} - U_j^T y_j */
    for (j = 0; j + 1 < nblk; j++)
        for (r = 0; r < nb; r++)
            for (c = 0; c < ncol; c++) {
                double acc = 0.0;
                for (q = 0; q < nb; q++)
                    acc += w->U[j * nb2 + q * nb + r] * X[(j * nb + q) * ncol + c];
                X[((j + 1) * nb + r) * ncol + c] -= acc;
            }
    /* z_j = P_j^-1 y_j (Cholesky factor where Pe = 0, else the eigen decomposition) */
    for (j = 0; j < nblk; j++) {
        const double *Pe = w->Pe + j * nb, *Pv = w->Pv + j * nb2;
        for (c = 0; c < ncol; c++) {
            double y[TR_BTD_MAXB], t[TR_BTD_MAXB];
            for (r = 0; r < nb; r++) y[r] = X[(j * nb + r) * ncol + c];
            if (Pe[0] == 0.0) {
                chol_solve(nb, Pv, y);
                for (r = 0; r < nb; r++) X[(j * nb + r) * ncol + c] = y[r];
                continue;
            }
            for (r = 0; r < nb; r++) {
                double acc = 0.0;
                for (q = 0; q < nb; q++) acc += Pv[q * nb + r] * y[q];
                t[r] = acc / Pe[r];
            }
            for (r = 0; r < nb; r++) {
                double acc = 0.0;
                for (q = 0; q < nb; q++) acc += Pv[r * nb + q] * t[q];
                X[(j * nb + r) * ncol + c] = acc;
            }
        }
    }
    /* back: x_j = z_j - U_j x_{j+1} */
    for (j = nblk - 2; j >= 0; j--)
        for (r = 0; r < nb; r++)
            for (c = 0; c < ncol; c++) {
                double acc = 0.0;
                for (q = 0; q < nb; q++)
                    acc += w->U[j * nb2 + r * nb + q] * X[((j + 1) * nb + q) * ncol + c];
                X[(j * nb + r) * ncol + c] -= acc;
            }
}

/* ------------------------------------------------------------ inertia */
/* The number of eigenvalues below lam of the bordered pencil (H, M), by the block
 * LDL^T of H - lam M and Haynsworth's additivity for the bordered columns; the factors
 * stay for tr_btd_solve.  *singular: a pivot was numerically zero (no count then). */
int tr_btd_count(tr_btd *w, double lam, int *singular)
{
    const int nblk = w->nblk, nb = w->nb, nbord = w->nbord, nb2 = nb * nb;
    double Pj[TR_BTD_MAXB * TR_BTD_MAXB], tmp[TR_BTD_MAXB * TR_BTD_MAXB];
    int j, r, c, q, neg = 0;
    *singular = 0;
    for (j = 0; j < nblk; j++) {
        double *Pe = w->Pe + j * nb, *Pv = w->Pv + j * nb2, emax = 0.0;
        for (r = 0; r < nb2; r++) Pj[r] = w->D[j * nb2 + r];
        for (r = 0; r < nb; r++) Pj[r * nb + r] -= lam * w->Mw[j * nb + r];
        if (j > 0) {
            /* - E_{j-1}^T U_{j-1} */
            const double *Ep = w->E + (j - 1) * nb2, *Up = w->U + (j - 1) * nb2;
            for (r = 0; r < nb; r++)
                for (c = 0; c < nb; c++) {
                    double acc = 0.0;
                    for (q = 0; q < nb; q++) acc += Ep[q * nb + r] * Up[q * nb + c];
                    Pj[r * nb + c] -= acc;
                }
        }
        for (r = 0; r < nb; r++)
            for (c = 0; c < r; c++)
                Pj[r * nb + c] = Pj[c * nb + r] = 0.5 * (Pj[r * nb + c] + Pj[c * nb + r]);
        if (chol(nb, Pj, Pv)) {
            /* positive definite (the common case): no negative pivot; Pe = 0 marks the
             * Cholesky factor in Pv */
            for (r = 0; r < nb; r++) Pe[r] = 0.0;
            if (j + 1 < nblk) {
                const double *Ej = w->E + j * nb2;
                double *Uj = w->U + j * nb2;
                for (c = 0; c < nb; c++) {
                    double col[TR_BTD_MAXB];
                    for (r = 0; r < nb; r++) col[r] = Ej[r * nb + c];
                    chol_solve(nb, Pv, col);
                    for (r = 0; r < nb; r++) Uj[r * nb + c] = col[r];
                }
            }
            continue;
        }
        sym_eig(nb, Pj, Pe, Pv); /* (the pivots are small: nb <= 6) */
        for (r = 0; r < nb; r++) {
            if (Pe[r] < 0.0) neg++;
            if (fabs(Pe[r]) > emax) emax = fabs(Pe[r]);
        }
        for (r = 0; r < nb; r++)
            if (!(fabs(Pe[r]) > 1e-13 * emax)) *singular = 1;
        if (*singular) return neg;
        if (j + 1 < nblk) {
            /* U_j = P_j^-1 E_j = V diag(1/e) V^T E_j */
            const double *Ej = w->E + j * nb2;
            double *Uj = w->U + j * nb2;
            for (r = 0; r < nb; r++)
                for (c = 0; c < nb; c++) {
                    double acc = 0.0;
                    for (q = 0; q < nb; q++) acc += Pv[q * nb + r] * Ej[q * nb + c];
                    tmp[r * nb + c] = acc / Pe[r];
                }
            for (r = 0; r < nb; r++)
                for (c = 0; c < nb; c++) {
                    double acc = 0.0;
                    for (q = 0; q < nb; q++) acc += Pv[r * nb + q] * tmp[q * nb + c];
                    Uj[r * nb + c] = acc;
                }
        }
    }
    if (nbord > 0) {
        double *X = w->X, *S = w->S;
        const int n = nblk * nb;
        int negS = 0;
        for (r = 0; r < n * nbord; r++) X[r] = w->B[r];
        tr_btd_solve(w, X, nbord);
        /* S = -C - B^T X */
        for (r = 0; r < nbord; r++)
            for (c = 0; c < nbord; c++) {
                double acc = 0.0;
                for (q = 0; q < n; q++) acc += w->B[q * nbord + r] * X[q * nbord + c];
                S[r * nbord + c] = -acc - (r == c ? w->cb[r] : 0.0);
            }
        for (r = 0; r < nbord; r++)
            for (c = 0; c < r; c++)
                S[r * nbord + c] = S[c * nbord + r] = 0.5 * (S[r * nbord + c] + S[c * nbord + r]);
        sym_eig(nbord, S, w->Se, w->Sv);
        {
            /* a (numerically) singular S: dependent constraints, no count */
            double smax = 0.0;
            for (r = 0; r < nbord; r++) smax = fmax(smax, fabs(w->Se[r]));
            for (r = 0; r < nbord; r++)
                if (!(fabs(w->Se[r]) > 1e-12 * smax)) *singular = 1;
        }
        for (r = 0; r < nbord; r++) negS += w->Se[r] < 0.0;
        neg += negS - nbord;
    }
    return neg;
}

/* The smallest eigenvalue of the bordered pencil, by bisection on the inertia:
 * bracketed by quadrupling from the sign at 0 (below0: the count at 0 was positive;
 * the stability margins are O(1)), within Gershgorin bounds of M^-1/2 H M^-1/2 (the
 * bordered terms only raise it); to 1e-9 absolute plus 1e-5 relative. */
double tr_btd_smallest(tr_btd *w, int below0)
{
    const int nblk = w->nblk, nb = w->nb, nb2 = nb * nb;
    double glo = INFINITY, ghi = -INFINITY, lo, hi, step;
    int j, r, c, it, sing;
    /* bounds from the rotation rows (Gershgorin on M^-1/2 H M^-1/2 over the coordinates
     * with a mass, the others' coupling counted at the smallest mass): generous, and
     * only limits the doubling below */
    {
        double mmin = INFINITY;
        for (j = 0; j < nblk * nb; j++)
            if (w->Mw[j] > 0.0) mmin = fmin(mmin, w->Mw[j]);
        for (j = 0; j < nblk; j++)
            for (r = 0; r < nb; r++) {
                const double mr = w->Mw[j * nb + r];
                double rad = 0.0;
                if (!(mr > 0.0)) continue;
                for (c = 0; c < nb; c++)
                    if (c != r) rad += fabs(w->D[j * nb2 + r * nb + c]);
                if (j + 1 < nblk)
                    for (c = 0; c < nb; c++) rad += fabs(w->E[j * nb2 + r * nb + c]);
                if (j > 0)
                    for (c = 0; c < nb; c++) rad += fabs(w->E[(j - 1) * nb2 + c * nb + r]);
                glo = fmin(glo, (w->D[j * nb2 + r * nb + r] - rad) / fmin(mr, mmin));
                ghi = fmax(ghi, (w->D[j * nb2 + r * nb + r] + rad) / mmin);
            }
    }
    glo = -fabs(glo) - 1.0, ghi = fabs(ghi) + 1.0;
    /* bracket [lo, hi] with count(lo) = 0 < count(hi) */
    if (below0) {
        hi = 0.0;
        for (step = 1.0, lo = -1.0; lo > glo; step *= 4.0, lo = -step) {
            int cnt = tr_btd_count(w, lo, &sing);
            if (sing) cnt = tr_btd_count(w, lo * (1.0 + 1e-9), &sing);
            if (cnt == 0) break;
            hi = lo;
        }
        if (lo < glo) lo = glo;
    } else {
        lo = 0.0;
        for (step = 1.0, hi = 1.0; hi < ghi; step *= 4.0, hi = step) {
            int cnt = tr_btd_count(w, hi, &sing);
            if (sing) cnt = tr_btd_count(w, hi * (1.0 + 1e-9), &sing);
            if (cnt >= 1) break;
            lo = hi;
        }
        if (hi > ghi) hi = ghi;
    }
    for (it = 0; it < 200 && hi - lo > 1e-9 + 1e-5 * (fabs(lo) + fabs(hi)); it++) {
        const double mid = 0.5 * (lo + hi);
        int cnt = tr_btd_count(w, mid, &sing);
        if (sing) cnt = tr_btd_count(w, mid + 1e-9 * (hi - lo), &sing);
        if (cnt >= 1)
            hi = mid;
        else
            lo = mid;
    }
    return 0.5 * (lo + hi);
}
