"""Stage 1, declare: what the user writes. Links and loads (elements), one-way parts,
tables, scenes, parameters with their units and assumptions, the declared
:class:`~mechdyn.declare.mechanism.Mechanism` and model files. Imports only the shared base.
"""
