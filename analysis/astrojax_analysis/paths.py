"""Where the package sits in the checkout: the repository's sweeps/ and build/ folders."""
import os

PACKAGE = os.path.dirname(os.path.abspath(__file__))
REPOSITORY = os.path.dirname(os.path.dirname(PACKAGE))  # analysis/astrojax_analysis -> the checkout
SWEEPS = os.path.join(REPOSITORY, "sweeps")
