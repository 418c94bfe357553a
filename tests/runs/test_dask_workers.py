"""Dask settings of one-simulation workers: the environment variables say what the config says."""

from __future__ import annotations

import pytest

from pinwind.runs.dask_workers import WORKER_CONFIG, worker_environment


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


def test_local_client_runs_tasks_and_closes_without_logging_an_error(capfd):
    pytest.importorskip("distributed")
    import logging

    from pinwind.runs.dask_workers import local_client

    records: list[logging.LogRecord] = []
    handler = logging.Handler(logging.WARNING)
    handler.emit = records.append  # type: ignore[method-assign]
    # distributed's loggers do not propagate to the root: listen on its own.
    logger = logging.getLogger("distributed")
    logger.addHandler(handler)
    disabled = logging.root.manager.disable
    try:
        with local_client(1, processes=False) as client:
            assert client.submit(sum, [1, 2]).result() == 3
    finally:
        logger.removeHandler(handler)
    assert [r.getMessage() for r in records if r.levelno >= logging.ERROR] == []
    assert "Traceback" not in capfd.readouterr().err
    # Logging is back as it was, for this process's own messages.
    assert logging.root.manager.disable == disabled
