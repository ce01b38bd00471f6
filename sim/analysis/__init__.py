"""Offline engineering analyses (linear stability, design checks): plain Python
over scipy, run from tests and from the command line, never in the cycle loop."""
