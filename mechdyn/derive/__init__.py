"""Stage 2, derive: sympy. Lagrange's equations of the second kind, the reduced inertia
and moment, transmission functions of closed loops, LaTeX, closed forms, linearisation and
modes. Imports the declare stage and the shared base.
"""
