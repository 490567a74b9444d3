"""Stage 6, report: documents made from everything before. The HTML report with the
derivation and results, and animations. Imports earlier stages only.
"""
