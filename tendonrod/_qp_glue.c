/*
 * _qp_glue.c -- _core.qp: the small dense convex QP of tr_qp.h on NumPy arrays.
 */
#include "_glue.h"
#include "tr_qp.h"

const char glue_qp_doc[] =
    "qp(H, g, A, G, h, x0, max_iter=200) -> (u, lam, mu, active): minimise\n"
    "1/2 u^T H u + g^T u subject to A u = b, G u >= h, from x0, which satisfies the\n"
    "equalities (b = A x0; a constraint x0 violates is relaxed to what x0 satisfies), by the\n"
    "primal active-set method (tr_qp).  H (n, n) symmetric positive definite, g (n,),\n"
    "A (me, n), G (mi, n), h (mi,), x0 (n,).  u (n,) the minimiser, lam (me,) and mu (mi,)\n"
    "the multipliers (H u + g = A^T lam + G^T mu, mu >= 0), active: a tuple of the indices\n"
    "of the inequalities that hold with equality at u.  ValueError for shapes that do not\n"
    "agree or non-finite entries, ArithmeticError for a singular reduced Hessian.";

/* A C-contiguous float64 copy of obj with nd dimensions, or NULL with ValueError naming
 * the argument. */
static PyArrayObject *as_array(PyObject *obj, int nd, const char *name)
{
    PyArrayObject *a = (PyArrayObject *)PyArray_FROMANY(obj, NPY_DOUBLE, nd, nd,
                                                        NPY_ARRAY_IN_ARRAY | NPY_ARRAY_ENSURECOPY);
    npy_intp i, size;
    const double *v;
    if (!a) {
        PyErr_Clear();
        PyErr_Format(PyExc_ValueError, "qp: %s must be a %d-d array of numbers", name, nd);
        return NULL;
    }
    size = PyArray_SIZE(a);
    v = (const double *)PyArray_DATA(a);
    for (i = 0; i < size; i++)
        if (!isfinite(v[i])) {
            Py_DECREF(a);
            PyErr_Format(PyExc_ValueError, "qp: %s has a non-finite entry", name);
            return NULL;
        }
    return a;
}

PyObject *glue_qp(PyObject *self, PyObject *args, PyObject *kwds)
{
    static char *kwlist[] = {"H", "g", "A", "G", "h", "x0", "max_iter", NULL};
    PyObject *oH, *og, *oA, *oG, *oh, *ox, *out = NULL, *act = NULL;
    PyArrayObject *H = NULL, *g = NULL, *A = NULL, *G = NULL, *h = NULL, *x = NULL;
    PyObject *u = NULL, *lam = NULL, *mu = NULL;
    int max_iter = 200, n, me, mi, status, i;
    double *work = NULL;
    int *active = NULL;
    npy_intp dn, dme, dmi;
    (void)self;
    if (!PyArg_ParseTupleAndKeywords(args, kwds, "OOOOOO|i:qp", kwlist, &oH, &og, &oA, &oG, &oh,
                                     &ox, &max_iter))
        return NULL;
    if (!(H = as_array(oH, 2, "H")) || !(g = as_array(og, 1, "g")) || !(A = as_array(oA, 2, "A")) ||
        !(G = as_array(oG, 2, "G")) || !(h = as_array(oh, 1, "h")) || !(x = as_array(ox, 1, "x0")))
        goto done;
    n = (int)PyArray_DIM(g, 0), me = (int)PyArray_DIM(A, 0), mi = (int)PyArray_DIM(G, 0);
    if (PyArray_DIM(H, 0) != n || PyArray_DIM(H, 1) != n || PyArray_DIM(A, 1) != n ||
        PyArray_DIM(G, 1) != n || PyArray_DIM(h, 0) != mi || PyArray_DIM(x, 0) != n ||
        max_iter < 0) {
        PyErr_Format(PyExc_ValueError,
                     "qp: shapes do not agree (H (n, n), g (n,), A (me, n), G (mi, n), h (mi,), "
                     "x0 (n,) with n = %d) or max_iter %d < 0",
                     n, max_iter);
        goto done;
    }
    dn = n, dme = me, dmi = mi;
    u = glue_array(1, &dn, NULL), lam = glue_array(1, &dme, NULL), mu = glue_array(1, &dmi, NULL);
    work = PyMem_Malloc((tr_qp_work_len(n, me, mi) + 1) * sizeof(double));
    active = PyMem_Malloc(((size_t)mi + 1) * sizeof(int));
    if (!u || !lam || !mu || !work || !active) {
        if (!PyErr_Occurred()) PyErr_NoMemory();
        goto done;
    }
    status =
        tr_qp(n, PyArray_DATA(H), PyArray_DATA(g), me, PyArray_DATA(A), mi, PyArray_DATA(G),
              PyArray_DATA(h), PyArray_DATA(x), max_iter, PyArray_DATA((PyArrayObject *)u),
              PyArray_DATA((PyArrayObject *)lam), PyArray_DATA((PyArrayObject *)mu), active, work);
    if (status == TR_EINVAL) {
        PyErr_Format(PyExc_ValueError, "qp: n = %d unknowns and %d constraints are out of range", n,
                     me + mi);
        goto done;
    }
    if (status < 0) {
        PyErr_SetString(PyExc_ArithmeticError,
                        "qp: singular reduced Hessian (H is not positive definite on the "
                        "working set's null space)");
        goto done;
    }
    if (!(act = PyTuple_New(status))) goto done;
    for (i = 0, status = 0; i < mi; i++) {
        PyObject *index;
        if (!active[i]) continue;
        if (!(index = PyLong_FromLong(i))) goto done;
        PyTuple_SET_ITEM(act, status++, index);
    }
    out = PyTuple_Pack(4, u, lam, mu, act);
done:
    Py_XDECREF(H), Py_XDECREF(g), Py_XDECREF(A), Py_XDECREF(G), Py_XDECREF(h), Py_XDECREF(x);
    Py_XDECREF(u), Py_XDECREF(lam), Py_XDECREF(mu), Py_XDECREF(act);
    PyMem_Free(work);
    PyMem_Free(active);
    return out;
}
