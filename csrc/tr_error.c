/* tr_error.c -- names of the status codes, and the message helpers. */
#include <stdarg.h>
#include <stdio.h>

#include "tendonrod.h"
#include "tr_internal.h"

const char *tr_strerror(int status)
{

    switch (status) {
    case TR_OK: return "success";
    case TR_TRUNCATION: return "converged; truncation estimate above tolerance at the step cap";
    case TR_ILLCONDITIONED: return "converged; final Jacobian nearly singular";
    case TR_OFFPATH: return "converged off the load path (continuation stalled), not confirmed";
    case TR_CONFIRMED:
        return "converged off the load path (continuation stalled), confirmed by a second "
               "formulation";
    case TR_UNSTABLE: return "converged to an unstable equilibrium";
    case TR_FRICTION_HELD:
        return "converged with channel friction; the frictionless twin of the state is unstable";
    case TR_ROUNDOFF: return "converged to the residual's round-off floor, which lies above tol";
    case TR_CONTINUE: return "iteration in progress";
    case TR_EINVAL: return "invalid model or option";
    case TR_ENOMEM: return "out of memory";
    case TR_EMAXITER: return "iteration limit reached";
    case TR_EMAXFEV: return "function-evaluation limit reached";
    case TR_ENOPROGRESS: return "line search made no progress";
    case TR_ENONFINITE: return "integration produced a non-finite value";
    case TR_ESINGULAR: return "singular Jacobian";
    case TR_EINDETERMINATE: return "statically indeterminate";
    case TR_ENOEQUILIBRIUM: return "no equilibrium exists";
    case TR_EPRETENSION: return "pretension not meaningful for this tendon set";
    case TR_EINTEGRATOR: return "adaptive integrator failed";
    case TR_ECONTINUATION: return "continuation failed";
    case TR_EBUDGET: return "work budget exhausted";
    case TR_EINTERRUPTED: return "interrupted";
    default: return "unknown status";
    }
}

void tr_msgf(char *msg, size_t len, const char *fmt, ...)
{
    va_list ap;
    if (!msg || len == 0) return;
    va_start(ap, fmt);
    vsnprintf(msg, len, fmt, ap);
    va_end(ap);
}

void tr_message_converged(char *msg, size_t len, int nit, double residual, double tol)
{
    tr_msgf(msg, len, "converged in %d iterations (scaled residual %.3g <= tol %.3g)", nit,
            residual, tol);
}

void tr_message_floor(char *msg, size_t len, int nit, double residual, double tol, double floor)
{
    tr_msgf(msg, len,
            "converged in %d iterations to the residual's round-off floor: the scaled residual "
            "%.3g is above tol %.3g but at or below the floor %.3g (the unit round-off times the "
            "largest internal force and moment the residual sums, in EI/L^2 and EI/L; large "
            "tensions), where it cannot be told from zero; a tol below the floor cannot be "
            "verified: loosen tol to at least %.2g",
            nit, residual, tol, floor, floor);
}

void tr_set_message(tr_data *d, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(d->message, TR_MSGLEN, fmt, ap);
    va_end(ap);
}
