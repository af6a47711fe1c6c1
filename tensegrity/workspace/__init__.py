"""The kinematic workspace (paper III.A-B): sweeps, nominal CoG, fitted curves, 20-face mapping,
queries.
"""
