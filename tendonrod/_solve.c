/*
 * _solve.c -- the raw solver entry points: _core.solve, _core.compliance,
 * _core.strerror, _core.is_planar (contract: csrc/README.md).
 */
#include "_glue.h"

/* The formulation a model compiled to, and the options a workspace used. */
PyObject *glue_formulation(const tr_model *m, const tr_data *d)
{
    PyObject *form = PyDict_New();
    if (!form) return NULL;
    if (glue_set(form, "planar", PyBool_FromLong(m->planar)) < 0 ||
        glue_set(form, "kirchhoff", PyBool_FromLong(m->kirchhoff)) < 0 ||
        glue_set(form, "n_unknowns", PyLong_FromLong(m->n_unknowns)) < 0 ||
        glue_set(form, "n_states", PyLong_FromLong(m->n_states)) < 0 ||
        glue_set(form, "n_segments", PyLong_FromLong(m->nseg)) < 0 ||
        glue_set(form, "n_length_states", PyLong_FromLong(m->ndisp)) < 0 ||
        glue_set(form, "n_stretch_terms", PyLong_FromLong(m->n_stretch)) < 0 ||
        glue_set(form, "distributed_load", PyBool_FromLong(m->has_dist || m->has_pdist)) < 0 ||
        glue_set(form, "n_partial_loads", PyLong_FromLong(m->nd)) < 0 ||
        glue_set(form, "n_sections", PyLong_FromLong(m->nsec)) < 0 ||
        glue_set(form, "precurved", PyBool_FromLong(m->precurved)) < 0 ||
        glue_set(form, "n_routed_tendons", PyLong_FromLong(m->n_routed)) < 0 ||
        glue_set(form, "shooting_segments", PyLong_FromLong(m->nshoot)) < 0 ||
        glue_set(form, "shooting_growth", PyFloat_FromDouble(m->shoot_growth)) < 0 ||
        glue_set(form, "shooting_auto", PyBool_FromLong(m->shoot_auto)) < 0)
        goto fail;
    if (d) {
        const tr_options *o = tr_data_options(d);
        tr_result r;
        tr_data_result(d, &r);
        if (glue_set(form, "tip_only", PyBool_FromLong(o->tip_only)) < 0 ||
            glue_set(form, "integrator", PyUnicode_FromString(glue_integrators[o->integrator])) <
                0 ||
            glue_set(form, "steps", PyLong_FromLong(o->integrator == TR_ADAPTIVE ? 0 : r.steps)) <
                0 ||
            glue_set(form, "slack_model", PyUnicode_FromString(glue_slack_models[o->slack_model])) <
                0 ||
            glue_set(form, "jacobian_method",
                     PyUnicode_FromString(glue_jacobians[o->jacobian_method])) < 0)
            goto fail;
    }
    return form;
fail:
    Py_DECREF(form);
    return NULL;
}

/* The solve dict of a workspace: the fields of its _core.Result (_result.c), and the
 * node arrays when the solve recorded them. */
PyObject *glue_solve_result(const tr_model *m, const tr_data *d, int status, PyObject *form)
{
    PyObject *r = glue_result_new(m, d, status, form), *res;
    tr_outputs o;
    npy_intp dims[3];
    int N;
    if (!r) return NULL;
    res = glue_result_dict(r);
    Py_DECREF(r);
    if (!res) return NULL;
    tr_data_outputs(d, &o);
    if (o.lazy) return res;
    N = o.nnode;
    dims[0] = N;
    if (glue_set(res, "s", glue_array(1, dims, o.s)) < 0) goto fail;
    dims[1] = 3;
    if (glue_set(res, "position", glue_array(2, dims, o.pos)) < 0 ||
        glue_set(res, "force", glue_array(2, dims, o.force)) < 0 ||
        glue_set(res, "moment", glue_array(2, dims, o.moment)) < 0)
        goto fail;
    dims[2] = 3;
    if (glue_set(res, "rotation", glue_array(3, dims, o.rot)) < 0) goto fail;
    dims[1] = m->nt;
    if (glue_set(res, "tendon_tension", glue_array(2, dims, o.node_tension)) < 0 ||
        glue_set(res, "tendon_rest", glue_array(2, dims, o.node_rest)) < 0)
        goto fail;
    return res;
fail:
    Py_DECREF(res);
    return NULL;
}

/* Positional scene arrays, then the keywords: guess, jacobian, options. */
static int parse_call(glue_args *a, PyObject *args, PyObject *kwds, const char *fn, int nextra,
                      double *extra, glue_poll *poll, PyObject **cancel)
{
    PyObject *rod, *tendons, *loads, *dist, *kw = NULL, *guess = NULL, *jac = NULL;
    int r = -1;
    memset(a, 0, sizeof *a);
    if (nextra ? !PyArg_ParseTuple(args, "OOOOd", &rod, &tendons, &loads, &dist, extra)
               : !PyArg_ParseTuple(args, "OOOO", &rod, &tendons, &loads, &dist))
        return -1;
    if (kwds && !(kw = PyDict_Copy(kwds))) return -1;
    guess = glue_take(kw, "guess");
    jac = glue_take(kw, "jacobian");
    *cancel = glue_take(kw, "cancel");
    if (glue_poll_init(poll, *cancel) == 0 && glue_scene(a, rod, tendons, loads, dist) == 0 &&
        glue_options(a, kw, fn) == 0 && glue_warm_start(a, guess, jac) == 0)
        r = 0;
    Py_XDECREF(kw);
    Py_XDECREF(guess);
    Py_XDECREF(jac);
    return r;
}

const char glue_solve_doc[] =
    "solve(rod, tendons, loads, dist, *, guess=None, jacobian=None, **options) -> dict\n\n"
    "Raw entry point of the Cosserat-rod/tendon shooting solver (contract: csrc/README.md).\n\n"
    "rod (6,) [L, EI, GJ, EA, GA, kirchhoff]; tendons (nt, 8) [offset, angle, slope, EA (inf:\n"
    "inextensible), end, control (0 displacement / 1 tension), value (q [m], > 0 retracts, or\n"
    "tau [N]), pretension [N]]; loads (nl, 7) [s, F (3), M (3)] world frame; dist (3,) N/m world.\n"
    "guess: None or (6 + 2 nt,) [n(0) world, m(0) world, tension, slack] (a previous result's\n"
    "base_state); jacobian: None or the 'jacobian' of a previous solve (reused when its shape\n"
    "matches).  options: the fields of DEFAULT_OPTIONS (integrator, steps, rtol, tol, max_iter,\n"
    "max_nfev, jacobian_method, slack_model, continuation, max_continuation, nodes,\n"
    "force_spatial, tip_only, shooting_segments), ranges in LIMITS.\n\n"
    "Returns a dict: status (0 ok, > 0 caveat, < 0 failure; strerror(status)), message, success\n"
    "(status >= 0 except 3, off the load path), nit, nfev (integrations, incl. the recording\n"
    "pass), njev, residual_norm (scaled max-norm), s (N,), position (N,3) world [m], rotation\n"
    "(N,3,3) body-to-world, force (N,3) and moment (N,3) internal backbone force/moment, world\n"
    "[N, N m], tension (nt,) [N], slack (nt,) [m], displacement (nt,) [m] (input q for\n"
    "displacement-controlled tendons; from the path length for tension-controlled ones),\n"
    "base_state (6 + 2 nt,) the guess format of this solution, unknowns (k,) scaled, jacobian\n"
    "(k,k) scaled, jacobian_cond (1-norm), truncation_estimate (NaN when steps were given or\n"
    "the integrator is adaptive), truncation_carried (True: that estimate is the bound carried\n"
    "from a verification at a nearby solution), verified_estimate and verified_unknowns (k,)\n"
    "(the step verification that vouches for the step count and the unknowns it measured at;\n"
    "NaN and None without one), continuation_steps, formulation (dict).\n";

PyObject *glue_solve(PyObject *self, PyObject *args, PyObject *kwds)
{
    glue_args a;
    glue_poll poll;
    tr_model *m = NULL;
    tr_data *d = NULL;
    PyObject *result = NULL, *cancel = NULL;
    const double *g = NULL, *jac = NULL;
    int status;
    if (parse_call(&a, args, kwds, "solve", 0, NULL, &poll, &cancel) < 0 ||
        glue_build(&a, NULL, &m, &d) < 0)
        goto done;
    g = a.guess ? (const double *)PyArray_DATA(a.guess) : NULL;
    if (a.jac && PyArray_DIM(a.jac, 0) == m->n_unknowns) jac = (const double *)PyArray_DATA(a.jac);
    tr_set_poll(d, glue_poll_hook, &poll);
    Py_BEGIN_ALLOW_THREADS;
    status = tr_solve(m, d, g, jac);
    Py_END_ALLOW_THREADS;
    if (glue_poll_finish(&poll, status) == 0) result = glue_solve_result(m, d, status, NULL);
done:
    Py_XDECREF(cancel);
    tr_data_free(d);
    tr_model_free(m);
    glue_args_clear(&a);
    return result;
}

const char glue_compliance_doc[] =
    "compliance(rod, tendons, loads, dist, s, *, guess=None, **options) -> (6, 6) array\n\n"
    "[dx (3), dtheta (3)] of the backbone point at arc length s per [force (3), moment (3)]\n"
    "applied there, world frame (dtheta: world rotation-vector increment), linearised at the\n"
    "solved state (solved first from `guess`, normally the solution's base state) with the\n"
    "prescribed displacements and tensions held fixed: implicit function theorem\n"
    "J du = -dF/dp with central differences on the shooting map (spatial formulation).\n"
    "Same options as solve (nodes, tip_only and force_spatial are ignored).  Raises\n"
    "RuntimeError with the solver's message if the state cannot be solved.\n";

PyObject *glue_compliance(PyObject *self, PyObject *args, PyObject *kwds)
{
    glue_args a;
    glue_poll poll;
    tr_model *m = NULL;
    tr_data *d = NULL;
    PyObject *result = NULL, *cancel = NULL;
    double s = 0.0, extra[TR_LD_NCOL] = {0, 0, 0, 0, 0, 0, 0}, C[36], L;
    int status;
    if (parse_call(&a, args, kwds, "compliance", 1, &s, &poll, &cancel) < 0) goto done;
    a.opt.force_spatial = a.opt.tip_only = 1;
    L = ((const double *)PyArray_DATA(a.rod))[TR_ROD_L];
    if (!(s > 0.0 && s <= L)) {
        glue_err(PyExc_ValueError, "s = %g must lie in (0, L = %g]", s, L);
        goto done;
    }
    extra[TR_LD_S] = s;
    if (glue_build(&a, extra, &m, &d) < 0) goto done;
    tr_set_poll(d, glue_poll_hook, &poll);
    Py_BEGIN_ALLOW_THREADS;
    status = tr_solve(m, d, a.guess ? (const double *)PyArray_DATA(a.guess) : NULL, NULL);
    if (TR_SUCCEEDED(status))
        status = tr_compliance(m, d, s, C);
    else if (status >= 0)
        status = TR_ECONTINUATION; /* linearising about an unvouched equilibrium: refuse */
    Py_END_ALLOW_THREADS;
    if (glue_poll_finish(&poll, status) < 0) goto done;
    if (status < 0) {
        glue_err(PyExc_RuntimeError, "compliance: %s (status %d: %s)", tr_data_message(d), status,
                 tr_strerror(status));
        goto done;
    }
    {
        npy_intp dims[2] = {6, 6};
        result = glue_array(2, dims, C);
    }
done:
    Py_XDECREF(cancel);
    tr_data_free(d);
    tr_model_free(m);
    glue_args_clear(&a);
    return result;
}

const char glue_strerror_doc[] = "strerror(status) -> str: the name of a solver status code.";

PyObject *glue_strerror(PyObject *self, PyObject *arg)
{
    long code = PyLong_AsLong(arg);
    if (code == -1 && PyErr_Occurred()) return NULL;
    return PyUnicode_FromString(tr_strerror((int)code));
}

const char glue_is_planar_doc[] =
    "is_planar(tendons, loads, dist, dloads=None, sections=None, routes=None) -> bool: whether\n"
    "a scene of these arrays (as for solve; dloads the (nd, 5) partial distributed loads,\n"
    "sections the (nsec, 8) backbone sections, routes the (nroute, 12) tendon paths) "
    "lies in the x-z plane and is solved with the planar formulation (unless force_spatial):\n"
    "every tendon at |sin angle| <= LIMITS['planar_sin'], no load with Fy, Mx or Mz, dist_y = 0.";

PyObject *glue_is_planar(PyObject *self, PyObject *args)
{
    glue_args a;
    PyObject *tendons, *loads, *dist, *dloads = NULL, *secs = NULL, *routes = NULL, *kw = NULL;
    PyObject *rod = NULL, *result = NULL;
    double r[TR_ROD_NCOL] = {1, 1, 1, 1, 1, 0};
    npy_intp six = TR_ROD_NCOL;
    memset(&a, 0, sizeof a);
    if (!PyArg_ParseTuple(args, "OOO|OOO", &tendons, &loads, &dist, &dloads, &secs, &routes))
        return NULL;
    if (!(rod = glue_array(1, &six, r))) return NULL;
    if (!(kw = PyDict_New()) ||
        (dloads && dloads != Py_None && glue_set(kw, "dloads", Py_NewRef(dloads)) < 0) ||
        (secs && secs != Py_None && glue_set(kw, "sections", Py_NewRef(secs)) < 0) ||
        (routes && routes != Py_None && glue_set(kw, "routes", Py_NewRef(routes)) < 0)) {
        Py_XDECREF(kw);
        Py_DECREF(rod);
        return NULL;
    }
    if (glue_scene(&a, rod, tendons, loads, dist) == 0 && glue_options(&a, kw, "is_planar") == 0)
        result = PyBool_FromLong(
            tr_is_planar_dist(a.nt > 0 ? (const double *)PyArray_DATA(a.tendons) : NULL, a.nt,
                              a.nl > 0 ? (const double *)PyArray_DATA(a.loads) : NULL, a.nl,
                              (const double *)PyArray_DATA(a.dist),
                              a.nd > 0 ? (const double *)PyArray_DATA(a.dloads) : NULL, a.nd) &&
            tr_sections_planar(a.nsec > 0 ? (const double *)PyArray_DATA(a.sections) : NULL,
                               a.nsec) &&
            a.nroute == 0);
    Py_XDECREF(kw);
    Py_DECREF(rod);
    glue_args_clear(&a);
    return result;
}
