"""Life: fatigue of gear teeth and bearings from a run's load histories, and load spectra.

Rainflow cycles, S-N curves and Palmgren-Miner damage over a site's wind (``cycles``,
``sn_curve``, ``site``, ``contact_stress``, ``root_stress``, ``tooth_damage``), ISO 281 bearing
life (``bearing_life``; over a fatigue set's bins: ``set_bearing_life``) and LDD/LRD load
spectra (``load_spectrum``). A fatigue set (``fatigue_set``) has its cases reduced to cycles
(``case_cycles``) and rated (``set_damage``); reading its file and running its cases is
``pinwind.runs`` (``fatigue_set_file``, ``case_runner``, ``set_load_spectra``), above this
package: nothing here reads a scenario or runs a case.
"""
