/*
 * _glue.h -- what the glue files share.  The glue (tendonrod/_*.c) is the only code
 * that speaks the CPython / NumPy C-API; it is built into one extension,
 * tendonrod._core, whose module definition is _core.c.
 *
 * Each wrapper has the same shape: parse, coerce (float64, C-contiguous), check
 * shapes with a message naming the argument, allocate outputs, release the GIL
 * around the core call, map status to data, clean up through one label.
 */
#ifndef TENDONROD_GLUE_H
#define TENDONROD_GLUE_H

#define PY_SSIZE_T_CLEAN
#include <Python.h>
#define PY_ARRAY_UNIQUE_SYMBOL tendonrod_ARRAY_API
#define PY_UFUNC_UNIQUE_SYMBOL tendonrod_UFUNC_API
#ifndef TENDONROD_GLUE_MAIN
#define NO_IMPORT_ARRAY
#define NO_IMPORT_UFUNC
/* _modes.c: the vibration modes of a Problem's solution (tr_modes) */
PyObject *glue_modes(PyObject *self, PyObject *args, PyObject *kwds);
extern const char glue_modes_doc[];
PyObject *glue_simulate(PyObject *self, PyObject *args, PyObject *kwds);
extern const char glue_simulate_doc[];

#endif
#include <numpy/arrayobject.h>
#include <numpy/ufuncobject.h>

#include "tendonrod.h"

/* _ufuncs.c */
int glue_add_ufuncs(PyObject *module);

/* _args.c: arguments shared by the solver entry points */
typedef struct {
    PyArrayObject *rod, *tendons, *loads, *dist; /* the scene's flat arrays */
    PyArrayObject *guess, *jac, *nodes;          /* optional */
    PyArrayObject *dloads;   /* optional (nd, 5) partial distributed loads [s0, s1, f (3)] */
    PyArrayObject *sections; /* optional (nsec, 8) backbone sections [end, EI, GJ, EA, GA, u*] */
    PyArrayObject *routes;   /* optional (nroute, 12) tendon paths [tendon, kind, s0, s1, p] */
    PyArrayObject *friction; /* optional (nt, 2) channel friction [mu, sliding (+1 in, -1 out)] */
    int nt, nl, nnode, nd, nsec, nroute, nfric;
    tr_options opt;
} glue_args;

/* Names of the choice options, in the order of their enums. */
extern const char *const glue_integrators[];
extern const char *const glue_jacobians[];
extern const char *const glue_slack_models[];

void glue_args_clear(glue_args *a);
/* Exception of `type` with a printf-style message. */
void glue_err(PyObject *type, const char *fmt, ...);
/* float64, C-contiguous copy-or-view of obj; NULL + TypeError naming `name`. */
PyArrayObject *glue_coerce(PyObject *obj, const char *name);
/* 0, or -1 with ValueError when an entry is not finite (+inf allowed in column
 * `posinf_col` of rows of `ncol` when posinf_col >= 0). */
int glue_all_finite(PyArrayObject *a, const char *name, int posinf_col, int ncol);
/* Remove `key` from the dict kw (may be NULL) and return it (a new reference), or
 * NULL when absent (no exception). */
PyObject *glue_take(PyObject *kw, const char *key);
/* The scene arrays rod (6,), tendons (nt, 8), loads (nl, 7), dist (3,) into a,
 * checked.  0, or -1 with an exception. */
int glue_scene(glue_args *a, PyObject *rod, PyObject *tendons, PyObject *loads, PyObject *dist);
/* The solver options in the dict kw (every remaining key must be one): a->opt starts
 * from tr_default_options() and is checked by tr_options_check; "nodes" sets
 * a->nnode / a->nodes, "dloads" the partial distributed loads a->dloads / a->nd.  `fn` names the entry point in errors.  0 or -1. */
int glue_options(glue_args *a, PyObject *kw, const char *fn);
/* The optional guess (6 + 2 nt,) and jacobian (square) of a warm start.  0 or -1. */
int glue_warm_start(glue_args *a, PyObject *guess, PyObject *jacobian);
/* Compile the model (with an extra point load row when extra_load != NULL) and its
 * workspace; ValueError with the core's message (it names the value).  0 or -1. */
int glue_build(glue_args *a, const double *extra_load, tr_model **mp, tr_data **dp);
/* A new float64 array of shape dims filled from src (may be NULL). */
PyObject *glue_array(int nd, const npy_intp *dims, const double *src);
/* Steal `value` into dict[key]; -1 on error (value released). */
int glue_set(PyObject *dict, const char *key, PyObject *value);

/* _poll.c: the poll hook of a solve running with the GIL released (Ctrl-C, a Cancel
 * token from another thread). */
typedef struct {
    PyObject *cancel; /* a Cancel token (borrowed, kept alive by the caller) or NULL */
    int raised;       /* 1 once a signal handler raised (the exception is pending) */
} glue_poll;
extern PyTypeObject glue_cancel_type;
/* Set up p for a call with the keyword cancel= (None or a Cancel).  0 or -1. */
int glue_poll_init(glue_poll *p, PyObject *cancel);
/* The hook given to tr_set_poll (ctx: a glue_poll). */
int glue_poll_hook(void *ctx);
/* After the GIL is back: -1 with KeyboardInterrupt pending if the solve was interrupted
 * (by a signal handler's exception, or a Cancel token), else 0. */
int glue_poll_finish(glue_poll *p, int status);

/* _problem.c: the compiled Problem type */
extern PyTypeObject glue_problem_type;
/* The formulation dict of a model (and the options of a workspace, if d != NULL). */
PyObject *glue_formulation(const tr_model *m, const tr_data *d);
/* The solve result dict of a workspace (_solve.c). */
PyObject *glue_solve_result(const tr_model *m, const tr_data *d, int status, PyObject *form);
/* _result.c: _core.Result, the fields of one solve copied out of the workspace, each
 * built on first access; `form` the formulation template (may be NULL). */
extern PyTypeObject glue_result_type;
PyObject *glue_result_new(const tr_model *m, const tr_data *d, int status, PyObject *form);
/* Its solve dict (no node arrays). */
PyObject *glue_result_dict(PyObject *result);

/* _solve.c, _batch.c: the entry points */
PyObject *glue_solve(PyObject *self, PyObject *args, PyObject *kwds);
PyObject *glue_compliance(PyObject *self, PyObject *args, PyObject *kwds);
PyObject *glue_strerror(PyObject *self, PyObject *arg);
PyObject *glue_is_planar(PyObject *self, PyObject *args);
PyObject *glue_solve_batch(PyObject *self, PyObject *args, PyObject *kwds);
extern const char glue_solve_doc[], glue_compliance_doc[], glue_strerror_doc[];
extern const char glue_is_planar_doc[], glue_solve_batch_doc[];
/* _path.c: the load path of a scene (tr_path) */
PyObject *glue_path(PyObject *self, PyObject *args, PyObject *kwds);
extern const char glue_path_doc[];
/* _problem.c: _core.Problem, a compiled scene with its workspace */
typedef struct {
    PyObject_HEAD tr_model *m;
    tr_data *d;
    int nnode_req;   /* the nodes asked for (int form), for the repr */
    int busy;        /* 1 while a call runs with the GIL released */
    int last_status; /* status of the last solve (TR_CONTINUE before any) */
    PyObject *form;  /* the formulation dict (all but the step count), built once */
} ProblemObject;
/* The cached formulation template of the results (NULL with an exception). */
PyObject *glue_problem_form(ProblemObject *self);
/* 0, or -1 with RuntimeError: not initialised, or busy in another thread. */
int glue_problem_check(ProblemObject *self);
/* A solution's scaled unknowns for this problem (float64, n_unknowns of them): a new
 * reference, or NULL with ValueError/TypeError set. */
PyArrayObject *glue_problem_unknowns(const ProblemObject *self, PyObject *obj);
/* _actuate.c: Problem.actuate, the inverse actuation's run (tr_actuate) */
PyObject *glue_problem_actuate(ProblemObject *self, PyObject *args, PyObject *kwds);
extern const char glue_problem_actuate_doc[];
/* _qp_glue.c: the small dense QP of the inverse actuation's steps (tr_qp) */
PyObject *glue_qp(PyObject *self, PyObject *args, PyObject *kwds);
extern const char glue_qp_doc[];

/* _modes.c: the vibration modes of a Problem's solution (tr_modes) */
PyObject *glue_modes(PyObject *self, PyObject *args, PyObject *kwds);
extern const char glue_modes_doc[];
PyObject *glue_simulate(PyObject *self, PyObject *args, PyObject *kwds);
extern const char glue_simulate_doc[];
PyObject *glue_dyn_segments(PyObject *self, PyObject *args, PyObject *kwds);
extern const char glue_dyn_segments_doc[];

#endif
