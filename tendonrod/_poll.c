/*
 * _poll.c -- Ctrl-C and cancellation for solves that run with the GIL released.
 *
 * The core calls a poll hook about every 2 ms of a solve (tr_set_poll).  The glue's
 * hook briefly takes the GIL and runs Python's signal handlers (PyErr_CheckSignals:
 * on the main thread a SIGINT raises KeyboardInterrupt there, on other threads it does
 * nothing), and reads a Cancel token that another thread may set; either stops the
 * solve.  The exception stays pending in the calling thread's state, so the entry
 * point returns NULL with it once the GIL is back.
 */
#include "_glue.h"

typedef struct {
    PyObject_HEAD volatile int flag;
} CancelObject;

static PyObject *cancel_set(CancelObject *self, PyObject *unused)
{
    self->flag = 1;
    Py_RETURN_NONE;
}

static PyObject *cancel_clear(CancelObject *self, PyObject *unused)
{
    self->flag = 0;
    Py_RETURN_NONE;
}

static PyObject *cancel_is_set(CancelObject *self, void *closure)
{
    return PyBool_FromLong(self->flag);
}

static PyMethodDef cancel_methods[] = {
    {"set", (PyCFunction)cancel_set, METH_NOARGS,
     "Ask every solve polling this token to stop (from any thread)."},
    {"clear", (PyCFunction)cancel_clear, METH_NOARGS, "Reset the token."},
    {NULL, NULL, 0, NULL}};

static PyGetSetDef cancel_getset[] = {
    {"is_set", (getter)cancel_is_set, NULL, "True once set() was called.", NULL},
    {NULL, NULL, NULL, NULL, NULL}};

PyTypeObject glue_cancel_type = {
    PyVarObject_HEAD_INIT(NULL, 0).tp_name = "tendonrod._core.Cancel",
    .tp_basicsize = sizeof(CancelObject),
    .tp_flags = Py_TPFLAGS_DEFAULT,
    .tp_doc = "Cancel() -> a token that stops the solves given it (cancel=) when set from "
              "another thread: worker threads of a batch or a sweep stop at their next poll.",
    .tp_new = PyType_GenericNew,
    .tp_methods = cancel_methods,
    .tp_getset = cancel_getset,
};

int glue_poll_init(glue_poll *p, PyObject *cancel)
{
    p->cancel = NULL;
    p->raised = 0;
    if (cancel && cancel != Py_None) {
        if (!PyObject_TypeCheck(cancel, &glue_cancel_type)) {
            PyErr_Format(PyExc_TypeError, "cancel must be a tendonrod._core.Cancel, got %R",
                         cancel);
            return -1;
        }
        p->cancel = cancel;
    }
    return 0;
}

int glue_poll_hook(void *ctx)
{
    glue_poll *p = (glue_poll *)ctx;
    PyGILState_STATE g;
    int r;
    if (p->raised) return 1;
    if (p->cancel && ((CancelObject *)p->cancel)->flag) return 1;
    g = PyGILState_Ensure();
    r = PyErr_CheckSignals();
    PyGILState_Release(g);
    if (r < 0) p->raised = 1;
    return p->raised;
}

int glue_poll_finish(glue_poll *p, int status)
{
    if (p->raised) return -1; /* the handler's exception (KeyboardInterrupt) is pending */
    if (status == TR_EINTERRUPTED) {
        PyErr_SetString(PyExc_KeyboardInterrupt, "the solve was cancelled");
        return -1;
    }
    return 0;
}
