"""Checks of the pipeline's results: `checks` returns numbers and verdicts, `report` writes them."""
