/*
 * tr_hybrid.c -- GSL's hybridsj (Powell's dogleg with a scaled trust region and
 * rank-1 updates) on the shooting residual and its forward-difference Jacobian:
 * jacobian_method = "hybrid".
 */
#include <math.h>
#include <string.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_multiroots.h>

#include "tendonrod.h"
#include "tr_internal.h"
#include "tru_math.h"

static int hyb_f(const gsl_vector *x, void *params, gsl_vector *f)
{
    tr_data *d = (tr_data *)params;
    return tr_residual(d->vm, d, x->data, f->data) == TR_OK ? GSL_SUCCESS : GSL_EBADFUNC;
}

static int hyb_jac(tr_data *d, const double *x, const double *f0, gsl_matrix *J)
{
    const int k = d->k;
    int j;
    if (d->nfev + k > d->opt.max_nfev) return GSL_EMAXITER;
    for (j = 0; j < k; j++)
        if (tr_fd_column(d->vm, d, x, f0, j, J->data + j, J->tda, 0) != TR_OK) return GSL_EBADFUNC;
    d->njev++;
    /* hybridsj factors each new Jacobian by QR: about twice an LU's multiply-adds */
    d->spent += 2.0 * tr_lu_work(k, tr_nonzero_fraction(J->data, k, J->tda));
    return GSL_SUCCESS;
}

static int hyb_df(const gsl_vector *x, void *params, gsl_matrix *J)
{
    tr_data *d = (tr_data *)params;
    if (tr_residual(d->vm, d, x->data, d->hyb_f) != TR_OK) return GSL_EBADFUNC;
    return hyb_jac(d, x->data, d->hyb_f, J);
}

static int hyb_fdf(const gsl_vector *x, void *params, gsl_vector *f, gsl_matrix *J)
{
    tr_data *d = (tr_data *)params;
    if (tr_residual(d->vm, d, x->data, f->data) != TR_OK) return GSL_EBADFUNC;
    return hyb_jac(d, x->data, f->data, J);
}

int tr_hybrid_run(const tr_model *m, tr_data *d, int max_iter)
{
    (void)m; /* the callbacks read the workspace's view */
    const int k = d->k;
    gsl_multiroot_function_fdf F;
    gsl_vector_view xv = gsl_vector_view_array(d->x, (size_t)k);
    gsl_multiroot_fdfsolver *s = d->hyb;
    int it = 0, st, i, j, status = TR_CONTINUE;
    F.f = hyb_f;
    F.df = hyb_df;
    F.fdf = hyb_fdf;
    F.n = (size_t)k;
    F.params = d;
    st = gsl_multiroot_fdfsolver_set(s, &F, &xv.vector);
    if (st != GSL_SUCCESS) status = st == GSL_EMAXITER ? TR_EMAXFEV : TR_ENONFINITE;
    while (status == TR_CONTINUE) {
        double fn = tru_maxnorm(s->f->data, k);
        if (fn <= tr_tol(d)) {
            status = TR_OK;
            break;
        }
        if (it >= max_iter) {
            status = TR_EMAXITER;
            break;
        }
        if (d->nfev >= d->opt.max_nfev) {
            status = TR_EMAXFEV;
            break;
        }
        st = gsl_multiroot_fdfsolver_iterate(s);
        it++;
        d->spent += 3.0 * tr_trsv_work(k); /* the dogleg's solves and the rank-1 update */
        if (st == GSL_EMAXITER)
            status = TR_EMAXFEV;
        else if (st == GSL_EBADFUNC)
            status = TR_ENONFINITE;
        else if (st != GSL_SUCCESS)
            status = TR_ENOPROGRESS;
    }
    if (st != GSL_EBADFUNC || it > 0) {
        memcpy(d->x, s->x->data, (size_t)k * sizeof(double));
        memcpy(d->f, s->f->data, (size_t)k * sizeof(double));
        for (i = 0; i < k; i++)
            for (j = 0; j < k; j++) d->J[i * k + j] = gsl_matrix_get(s->J, i, j);
        d->have_J = 1;
        d->J_fresh = 0;
    }
    d->fnorm = tru_maxnorm(d->f, k);
    d->nit += it;
    switch (status) {
    case TR_OK: break;
    case TR_EMAXITER:
        tr_set_message(d,
                       "did not converge in %d iterations (hybrid; scaled residual %.3g > tol "
                       "%.3g); raise max_iter",
                       max_iter, d->fnorm, tr_tol(d));
        break;
    case TR_EMAXFEV:
        tr_set_message(d,
                       "function-evaluation limit (max_nfev = %d) reached (hybrid; scaled "
                       "residual %.3g); raise max_nfev",
                       d->opt.max_nfev, d->fnorm);
        break;
    case TR_ENONFINITE:
        tr_set_message(d, "the residual became non-finite in the hybrid iteration");
        break;
    default:
        tr_set_message(d,
                       "the hybrid (dogleg) iteration made no progress at scaled residual %.3g "
                       "(GSL: %s); the scene may have no equilibrium nearby",
                       d->fnorm, gsl_strerror(st));
    }
    return status;
}
