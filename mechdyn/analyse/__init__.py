"""Stage 5, analyse: what is computed from simulations and derivations. Steady periodic
motion, speed fluctuation and flywheels, sweeps, duty cycles, work-precision, motor
characteristics, linkage kinematics, kinetostatics and balancing. Imports earlier stages.
"""
