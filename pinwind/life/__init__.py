"""Fatigue life: rainflow cycles, S-N curves and Palmgren-Miner damage over a site's wind."""
