"""Rolling locomotion (paper III.C-D): workspace lookup, planning, controllers, runs, demos."""
