"""Rainflow counting of reversals (ASTM E1049-85 §5.4.4), compiled (life/cpp/rainflow.cpp)."""

import numpy as np

def extract_cycles(reversals: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(ranges, means, counts) of the cycles of a series of reversals, as ``rainflow`` counts."""

def closed_cycles(
    reversals: np.ndarray,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(ranges, means, counts, residue): the cycles before the last half cycles, and the stack.

    ``closed_cycles`` of the residue followed by the next reversals continues the count;
    ``extract_cycles`` of the last residue gives the last half cycles.
    """
