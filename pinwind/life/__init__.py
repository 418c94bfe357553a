"""Life: fatigue of gear teeth and bearings from a run's load histories, and load spectra."""
