"""The robot and how it moves (docs/design.md §1-4): arrays in, arrays out.

Never reads or writes files, draws, or knows Snakemake (tests/test_layers.py holds this).
"""
