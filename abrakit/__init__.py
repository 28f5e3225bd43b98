"""abrakit: the abrasive-wear modelling chain of Hoormazdi (2021), readable and verified."""

__version__ = "0.1.0"
