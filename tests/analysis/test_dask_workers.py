"""Dask settings of one-simulation workers: the environment variables say what the config says."""

from __future__ import annotations

import pytest

from pinwind.analysis.dask_workers import WORKER_CONFIG, worker_environment


def test_worker_environment_read_by_dask_gives_worker_config():
    """Dask's own reader of ``DASK_*`` variables turns them back into the same keys and values."""
    dask_config = pytest.importorskip("dask.config")
    read = dask_config.collect_env(worker_environment())
    for key, value in WORKER_CONFIG.items():
        # Dask's get treats "-" and "_" in a key as one, as it does for the variables.
        assert dask_config.get(key, config=read) == value, key


def test_worker_config_names_only_keys_dask_has():
    """A misspelt key would be ignored silently by Dask: each must exist in its defaults."""
    dask = pytest.importorskip("dask")
    pytest.importorskip("distributed")
    for key in WORKER_CONFIG:
        dask.config.get(key)  # KeyError for an unknown key
