/* mechdyn's FMI 2.0 Model Exchange glue: one instance holds time, state x = [q, u],
   parameters p (inputs among them), the switch flags w and the stop conditions' last
   sides. model.c defines the sizes and md_system, md_outputs, md_indicators, then
   includes this file. Value references: x (2 NQ), der(x) (2 NQ), p (NP: the
   CALCULATED ones md_calculated computes from the others), outputs (NOUT, then
   kinetic, potential and total energy). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "fmi2_header.h"

#define NX (2 * NQ)
#define NZ (NSTOP + NSW)
#define NY (NOUT + 2)
#define N_REAL (2 * NX + NP + NY + 1)
#define CHATTER 100     /* events in one instant after which the run stops */

typedef struct {
    double t, span;
    double x[NX + 1], p[NP + 1], w[NSW + 1], side[NSTOP + 1];
    double last_event;
    int terminated, quick_events;
    char name[128];
    fmi2CallbackFunctions callbacks;
} Instance;

static double sign_of(double v) { return v > 0.0 ? 1.0 : (v < 0.0 ? -1.0 : 0.0); }

/* M a = f: M's lower triangle row by row, by a dense Cholesky factorisation; returns 0
   where M is not positive definite (a is NaN then). */
static int solve_spd(const double *lower, const double *f, double *a)
{
    double L[NQ][NQ], z[NQ];
    int i, j, k, n = 0;
    for (i = 0; i < NQ; i++)
        for (j = 0; j <= i; j++)
            L[i][j] = lower[n++];
    for (i = 0; i < NQ; i++) {
        for (j = 0; j <= i; j++) {
            double s = L[i][j];
            for (k = 0; k < j; k++)
                s -= L[i][k] * L[j][k];
            if (i == j) {
                if (!(s > 0.0)) {
                    for (k = 0; k < NQ; k++) a[k] = NAN;
                    return 0;
                }
                L[i][i] = sqrt(s);
            } else {
                L[i][j] = s / L[j][j];
            }
        }
    }
    for (i = 0; i < NQ; i++) {
        double s = f[i];
        for (k = 0; k < i; k++) s -= L[i][k] * z[k];
        z[i] = s / L[i][i];
    }
    for (i = NQ - 1; i >= 0; i--) {
        double s = z[i];
        for (k = i + 1; k < NQ; k++) s -= L[k][i] * a[k];
        a[i] = s / L[i][i];
    }
    return 1;
}

static int derivatives(double t, const double *x, const double *p, const double *w, double *dx)
{
    double system[NQ * (NQ + 1) / 2 + NQ];
    int i;
    md_system(t, x, p, w, system);
    for (i = 0; i < NQ; i++) dx[i] = x[NQ + i];
    return solve_spd(system, system + NQ * (NQ + 1) / 2, dx + NQ);
}

/* The side of each switching function; one that is exactly zero takes the side it
   moves to (looked up a moment later along the motion, its own flag unlocked), as
   mechdyn's driver does; one still zero there (a position at rest: its speed is zero)
   takes the positive side unless the motion that side's equations start leaves it
   (looked up at q + tau^2/2 a, u + tau a: by the acceleration), as the driver's event
   at the start then decides. */
static void update_flags(Instance *m)
{
    double z[NZ + 1], ahead[NZ + 1], dx[NX], x[NX], w[NSW + 1];
    double span = m->span > 0.0 ? m->span : 1.0, delta = 1e-9 * span, tau = 3e-5 * span;
    int k, i, zero = 0;
    md_indicators(m->t, m->x, m->p, m->w, z);
    for (k = 0; k < NSW; k++) {
        w[k] = sign_of(z[NSTOP + k]);
        zero |= w[k] == 0.0;
    }
    if (zero) {
        derivatives(m->t, m->x, m->p, w, dx);
        for (i = 0; i < NX; i++) x[i] = m->x[i] + delta * dx[i];
        md_indicators(m->t + delta, x, m->p, w, ahead);
        zero = 0;
        for (k = 0; k < NSW; k++)
            if (w[k] == 0.0) {
                w[k] = sign_of(ahead[NSTOP + k]);
                zero |= w[k] == 0.0;
            }
    }
    if (zero) {
        int undecided[NSW + 1];
        for (k = 0; k < NSW; k++) {
            undecided[k] = w[k] == 0.0;
            if (undecided[k]) w[k] = 1.0;
        }
        derivatives(m->t, m->x, m->p, w, dx);
        for (i = 0; i < NQ; i++) {
            x[i] = m->x[i] + tau * dx[i] + 0.5 * tau * tau * dx[NQ + i];
            x[NQ + i] = m->x[NQ + i] + tau * dx[NQ + i];
        }
        md_indicators(m->t + tau, x, m->p, w, ahead);
        for (k = 0; k < NSW; k++)
            if (undecided[k] && ahead[NSTOP + k] < 0.0) w[k] = -1.0;
    }
    for (k = 0; k < NSW; k++) m->w[k] = w[k] == 0.0 ? 1.0 : w[k];
}

/* Whether a stop condition was crossed (in its direction) since the last event; the
   last non-zero side of each is remembered. */
static int stop_reached(Instance *m)
{
    double z[NZ + 1];
    int k, reached = 0;
    md_indicators(m->t, m->x, m->p, m->w, z);
    for (k = 0; k < NSTOP; k++) {
        double now = sign_of(z[k]), before = m->side[k];
        if (before != 0.0 && now != before &&
            (STOP_DIRECTION[k] == 0 || STOP_DIRECTION[k] == -before))
            reached = 1;
        if (now != 0.0) m->side[k] = now;
    }
    return reached;
}

/* The calculated parameters (given as expressions of others) from the tunable ones. */
static void calculate(Instance *m)
{
    double out[NCALC + 1];
    int i;
    md_calculated(m->t, m->x, m->p, m->w, out);
    for (i = 0; i < NCALC; i++) m->p[CALCULATED[i]] = out[i];
}

static int is_calculated(int k)
{
    int i;
    for (i = 0; i < NCALC; i++)
        if (CALCULATED[i] == k) return 1;
    return 0;
}

static double real_value(Instance *m, fmi2ValueReference vr)
{
    double dx[NX], y[NY + 1];
    if (vr < NX) return m->x[vr];
    if (vr < 2 * NX) {
        derivatives(m->t, m->x, m->p, m->w, dx);
        return dx[vr - NX];
    }
    if (vr < 2 * NX + NP) return m->p[vr - 2 * NX];
    md_outputs(m->t, m->x, m->p, m->w, y);
    vr -= 2 * NX + NP;
    return vr < NY ? y[vr] : y[NOUT] + y[NOUT + 1];
}

/* ------------------------------------------------------------ FMI 2.0 functions */
FMI2_Export const char *fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }
FMI2_Export const char *fmi2GetVersion(void) { return fmi2Version; }

FMI2_Export fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean on, size_t n,
                                           const fmi2String categories[])
{
    (void)c; (void)on; (void)n; (void)categories;
    return fmi2OK;
}

FMI2_Export fmi2Component fmi2Instantiate(fmi2String name, fmi2Type type, fmi2String guid,
                                          fmi2String location,
                                          const fmi2CallbackFunctions *callbacks,
                                          fmi2Boolean visible, fmi2Boolean logging)
{
    Instance *m;
    (void)location; (void)visible; (void)logging;
    if (type != fmi2ModelExchange || guid == NULL || strcmp(guid, MODEL_GUID) != 0)
        return NULL;
    m = (Instance *)calloc(1, sizeof(Instance));
    if (m == NULL) return NULL;
    memcpy((void *)&m->callbacks, callbacks, sizeof(fmi2CallbackFunctions));
    strncpy(m->name, name ? name : "mechdyn", sizeof(m->name) - 1);
    memcpy(m->x, START_X, sizeof(double) * NX);
    memcpy(m->p, START_P, sizeof(double) * (NP + 1));
    calculate(m);
    m->t = START_TIME;
    m->span = STOP_TIME - START_TIME;
    m->last_event = -INFINITY;
    return m;
}

FMI2_Export void fmi2FreeInstance(fmi2Component c) { free(c); }

FMI2_Export fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean toleranceDefined,
                                           fmi2Real tolerance, fmi2Real startTime,
                                           fmi2Boolean stopTimeDefined, fmi2Real stopTime)
{
    Instance *m = (Instance *)c;
    (void)toleranceDefined; (void)tolerance;
    m->t = startTime;
    if (stopTimeDefined && stopTime > startTime) m->span = stopTime - startTime;
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2EnterInitializationMode(fmi2Component c) { (void)c; return fmi2OK; }

FMI2_Export fmi2Status fmi2ExitInitializationMode(fmi2Component c)
{
    Instance *m = (Instance *)c;
    update_flags(m);
    memset(m->side, 0, sizeof(m->side));
    stop_reached(m);
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2Terminate(fmi2Component c) { (void)c; return fmi2OK; }

FMI2_Export fmi2Status fmi2Reset(fmi2Component c)
{
    Instance *m = (Instance *)c;
    memcpy(m->x, START_X, sizeof(double) * NX);
    memcpy(m->p, START_P, sizeof(double) * (NP + 1));
    calculate(m);
    memset(m->w, 0, sizeof(m->w));
    m->t = START_TIME;
    m->terminated = m->quick_events = 0;
    m->last_event = -INFINITY;
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                                   fmi2Real value[])
{
    size_t i;
    for (i = 0; i < n; i++) {
        if (vr[i] >= N_REAL) return fmi2Error;
        value[i] = real_value((Instance *)c, vr[i]);
    }
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                                   const fmi2Real value[])
{
    Instance *m = (Instance *)c;
    size_t i;
    for (i = 0; i < n; i++) {
        if (vr[i] < NX) m->x[vr[i]] = value[i];
        else if (vr[i] >= 2 * NX && vr[i] < 2 * NX + NP && !is_calculated(vr[i] - 2 * NX))
            m->p[vr[i] - 2 * NX] = value[i];
        else return fmi2Error;          /* derivatives, calculated parameters, outputs */
    }
    calculate(m);
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[],
                                      size_t n, fmi2Integer value[])
{ (void)c; (void)vr; (void)value; return n ? fmi2Error : fmi2OK; }
FMI2_Export fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[],
                                      size_t n, fmi2Boolean value[])
{ (void)c; (void)vr; (void)value; return n ? fmi2Error : fmi2OK; }
FMI2_Export fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference vr[],
                                     size_t n, fmi2String value[])
{ (void)c; (void)vr; (void)value; return n ? fmi2Error : fmi2OK; }
FMI2_Export fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[],
                                      size_t n, const fmi2Integer value[])
{ (void)c; (void)vr; (void)value; return n ? fmi2Error : fmi2OK; }
FMI2_Export fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[],
                                      size_t n, const fmi2Boolean value[])
{ (void)c; (void)vr; (void)value; return n ? fmi2Error : fmi2OK; }
FMI2_Export fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference vr[],
                                     size_t n, const fmi2String value[])
{ (void)c; (void)vr; (void)value; return n ? fmi2Error : fmi2OK; }

/* Not supported (canGetAndSetFMUstate, providesDirectionalDerivative are false). */
FMI2_Export fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate *s)
{ (void)c; (void)s; return fmi2Error; }
FMI2_Export fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate s)
{ (void)c; (void)s; return fmi2Error; }
FMI2_Export fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate *s)
{ (void)c; (void)s; return fmi2Error; }
FMI2_Export fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate s, size_t *n)
{ (void)c; (void)s; (void)n; return fmi2Error; }
FMI2_Export fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate s,
                                             fmi2Byte b[], size_t n)
{ (void)c; (void)s; (void)b; (void)n; return fmi2Error; }
FMI2_Export fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte b[], size_t n,
                                               fmi2FMUstate *s)
{ (void)c; (void)s; (void)b; (void)n; return fmi2Error; }
FMI2_Export fmi2Status fmi2GetDirectionalDerivative(
    fmi2Component c, const fmi2ValueReference u[], size_t nu, const fmi2ValueReference z[],
    size_t nz, const fmi2Real dv[], fmi2Real dz[])
{ (void)c; (void)u; (void)nu; (void)z; (void)nz; (void)dv; (void)dz; return fmi2Error; }

/* ------------------------------------------------------------ Model Exchange */
FMI2_Export fmi2Status fmi2EnterEventMode(fmi2Component c) { (void)c; return fmi2OK; }

FMI2_Export fmi2Status fmi2NewDiscreteStates(fmi2Component c, fmi2EventInfo *info)
{
    Instance *m = (Instance *)c;
    info->newDiscreteStatesNeeded = fmi2False;
    info->nominalsOfContinuousStatesChanged = fmi2False;
    info->valuesOfContinuousStatesChanged = fmi2False;
    info->nextEventTimeDefined = fmi2False;
    info->nextEventTime = 0.0;
    if (m->t - m->last_event <= 1e-9 * (fabs(m->t) > 1.0 ? fabs(m->t) : 1.0))
        m->quick_events++;
    else
        m->quick_events = 0;
    m->last_event = m->t;
    if (m->quick_events > CHATTER) {
        if (m->callbacks.logger)
            m->callbacks.logger(m->callbacks.componentEnvironment, m->name, fmi2Error,
                                "logStatusError", "events chatter at t = %g: a switch (a "
                                "sign, Abs, Min, Max or Piecewise of the state) flips back and "
                                "forth in one instant; a force that holds a speed at zero is a "
                                "friction element, which has no FMU form yet", m->t);
        return fmi2Error;
    }
    if (stop_reached(m)) m->terminated = 1;
    update_flags(m);
    info->terminateSimulation = m->terminated ? fmi2True : fmi2False;
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2EnterContinuousTimeMode(fmi2Component c) { (void)c; return fmi2OK; }

FMI2_Export fmi2Status fmi2CompletedIntegratorStep(fmi2Component c,
                                                   fmi2Boolean noSetFMUStatePriorToCurrentPoint,
                                                   fmi2Boolean *enterEventMode,
                                                   fmi2Boolean *terminateSimulation)
{
    (void)c; (void)noSetFMUStatePriorToCurrentPoint;
    *enterEventMode = fmi2False;
    *terminateSimulation = fmi2False;
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2SetTime(fmi2Component c, fmi2Real time)
{
    ((Instance *)c)->t = time;
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2SetContinuousStates(fmi2Component c, const fmi2Real x[], size_t n)
{
    if (n != NX) return fmi2Error;
    memcpy(((Instance *)c)->x, x, sizeof(double) * NX);
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2GetDerivatives(fmi2Component c, fmi2Real dx[], size_t n)
{
    Instance *m = (Instance *)c;
    size_t i;
    int finite;
    if (n != NX) return fmi2Error;
    finite = derivatives(m->t, m->x, m->p, m->w, dx);
    for (i = 0; i < NX; i++) finite = finite && isfinite(dx[i]);
    if (finite) return fmi2OK;
    if (m->callbacks.logger)
        m->callbacks.logger(m->callbacks.componentEnvironment, m->name, fmi2Error,
                            "logStatusError", "derivatives not finite at t = %g: the mass "
                            "matrix is not positive definite there, or an expression (a root, "
                            "power, logarithm or arcsine) has no real value", m->t);
    return fmi2Error;
}

FMI2_Export fmi2Status fmi2GetEventIndicators(fmi2Component c, fmi2Real z[], size_t n)
{
    Instance *m = (Instance *)c;
    double all[NZ + 1];
    if (n != NZ) return fmi2Error;
    md_indicators(m->t, m->x, m->p, m->w, all);
    memcpy(z, all, sizeof(double) * NZ);
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2GetContinuousStates(fmi2Component c, fmi2Real x[], size_t n)
{
    if (n != NX) return fmi2Error;
    memcpy(x, ((Instance *)c)->x, sizeof(double) * NX);
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2GetNominalsOfContinuousStates(fmi2Component c, fmi2Real x[],
                                                         size_t n)
{
    size_t i;
    (void)c;
    for (i = 0; i < n; i++) x[i] = 1.0;
    return fmi2OK;
}
