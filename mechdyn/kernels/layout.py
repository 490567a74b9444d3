"""Numbers shared by the compiled kernel and its Python callers: methods, statuses, the
layout of the ``carry`` vector and of the ``counts`` vector, event directions.

Plain module-level integers, so numba folds them into the compiled code as constants.

>>> carry_size(n=4, n_events=2)
20
"""

# ----------------------------------------------------------------------------- methods
DOP853 = 0    #: explicit Dormand-Prince 8(5,3), 7th-order dense output (Hairer)
RODAS5P = 1   #: Rosenbrock 5(4), 4th-order dense output (Steinebach 2023): stiff
METHOD_NAMES = ("DOP853", "Rodas5P")
DEGREE = (7, 4)   #: degree of each method's dense-output polynomial
MAX_DEGREE = 7

# ---------------------------------------------------------------------------- statuses
FINISHED = 0          #: reached t_bound
EVENT = 1             #: stopped at the earliest event (``fired`` says which, and how)
CHUNK_FULL = 2        #: took ``max_steps`` steps; call again to continue
STIFF = 3             #: DOP853: Hairer's stiffness test hit 15 times; switch to RODAS5P
NONSTIFF = 4          #: RODAS5P: h * spectral radius stayed small; DOP853 would do
STEP_TOO_SMALL = -1   #: the step size fell below 10 ulp of t
NOT_FINITE = -2       #: NaN/Inf in the derivative that shrinking the step cannot avoid
INVALID_INPUT = -3    #: inconsistent array sizes or values (the Python side names them)
STATUS_NAMES = {FINISHED: "finished", EVENT: "event", CHUNK_FULL: "chunk full",
                STIFF: "stiff", NONSTIFF: "non-stiff", STEP_TOO_SMALL: "step too small",
                NOT_FINITE: "not finite", INVALID_INPUT: "invalid input"}

# -------------------------------------------------------------------- event directions
EITHER = 0      #: fire on any sign change
RISING = 1      #: fire when g goes from negative to positive
FALLING = -1    #: fire when g goes from positive to negative
IGNORED = 2     #: do not watch this event function

# ------------------------------------------------------- carry: the state between calls
T = 0               #: current time
H = 1               #: step size to try next (<= 0: the kernel chooses one)
H_ACCEPTED = 2      #: last accepted step (RODAS5P's predictive controller; 0: none yet)
ERR_ACCEPTED = 3    #: its error norm (DOP853: the last trusted one, see blind_guard)
REJECTED = 4        #: 1 if the last attempt was rejected (no growth on the next step)
STIFF_HITS = 5      #: DOP853: stiffness-test hits since the last quiet spell (IASTI)
QUIET_STEPS = 6     #: DOP853: non-stiff test results since the last hit (NONSTI);
                    #: RODAS5P: settled steps with h * rho below NONSTIFF_LIMIT
H_RHO = 7           #: the last stiffness estimate h * spectral radius
EVENTS_VALID = 8    #: 1 if the event sign memory belongs to the current event functions
METHOD = 9          #: the method of the last call (a change resets the controller)
HEAD = 10           #: then y (n), the power-iteration vector (n), event sign memory (m)
                    #: (a memory of +1/-1 is the side of an event function while it
                    #: is zero; +2/-2 at the start of a call: that side whatever its
                    #: value, as a locked branch's switching function is watched)


def carry_size(n, n_events):
    """Length of the carry vector of a system with ``n`` states and ``n_events`` events."""
    return HEAD + 2 * n + n_events


# ------------------------------------------------------------------------------ counts
NFEV = 0       #: right-hand side evaluations (finite-difference Jacobians included)
NJEV = 1       #: analytic Jacobian evaluations, or finite-difference Jacobians formed
NLU = 2        #: LU decompositions
NACCEPT = 3    #: accepted steps
NREJECT = 4    #: rejected steps
NGEV = 5       #: event-function evaluations
N_COUNTS = 6
COUNT_NAMES = ("nfev", "njev", "nlu", "naccept", "nreject", "ngev")

# ------------------------------------------------------------- stiffness-switch tests
STIFF_LIMIT = 6.1       #: DOP853: h * rho above this is a hit (Hairer's dop853.f)
STIFF_HITS_TO_REPORT = 15
QUIET_TO_FORGET = 6     #: DOP853: this many non-stiff results in a row clear the hits
NONSTIFF_LIMIT = 1.5    #: RODAS5P: h * rho below this (a quarter of DOP853's limit) ...
NONSTIFF_STEPS = 20     #: ... for this many accepted steps (not growing 2x or more) in a
                        #: row, with no step above it in between, reports NONSTIFF
