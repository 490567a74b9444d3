"""Stage 3, compile: code generation. A scene's derived equations become Python source
(shared subexpressions, parameters passed at run time, Jacobian), cached on disk, executed
as plain Python or compiled by numba for the kernels. Imports earlier stages only.
"""
