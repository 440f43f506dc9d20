"""ggins campaign: Monte Carlo sets and parameter sweeps of the ggins commands, on Dask."""
