"""Write pinwind model files (docs/model_format.md) from tooth counts, modules and face widths.

Each builder returns URDF text with a ``<gearbox>`` extension that ``pinwind.model.gearbox.load``
accepts. Arguments are SI (module and face width [m], pressure angle [rad]); the file carries the
``_mm`` / ``_deg`` attributes of the format. Layout (every builder): shafts along the world z
axis, root link ``housing``, gravity along −y.

- ``planetary_urdf`` (``planetary.py``): a planetary stage with a fixed ring, plus parallel
  stages; ``write_planetary`` writes it to a file.
- ``compound_planetary_urdf`` (``compound_planetary.py``): stepped planets, fixed ring.
- ``parallel_urdf`` (``parallel.py``): parallel-axis stages alone.
- ``split_shaft_pair_urdf`` (``split_shaft_pair.py``): a spur pair on torsionally split shafts.
- ``stages_urdf`` (``stages.py``): any sequence of planetary and parallel stages joined by
  named shafts, with bearings, rotor and generator; ``read_stage_file`` (``stage_file.py``)
  reads them from a TOML stage file (``pinwind build stages``).

Shared parts: the carrier (``carrier.py``), the default steel bodies (``gear_bodies.py``), the
profile shift for a centre distance (``centre_distance.py``), the argument checks
(``arguments.py``) and the URDF writer (``urdf_writer.py``).
"""

from pinwind.model.builders.carrier import CARRIER_THICKNESS_FRACTION
from pinwind.model.builders.centre_distance import shift_sum_for_centre_distance
from pinwind.model.builders.compound_planetary import compound_planetary_urdf
from pinwind.model.builders.gear_bodies import (
    RING_RIM_MODULES,
    STEEL_DENSITY,
    MassProperties,
    cylinder_inertia,
    steel_cylinder,
)
from pinwind.model.builders.parallel import parallel_urdf
from pinwind.model.builders.planetary import planetary_urdf, write_planetary
from pinwind.model.builders.split_shaft_pair import split_shaft_pair_urdf
from pinwind.model.builders.stage_file import read_stage_file, solid_shaft_stiffness
from pinwind.model.builders.stages import (
    EndBody,
    ParallelStage,
    PlanetaryStage,
    StageBearing,
    StageGear,
    check_stage_meshes,
    stages_urdf,
)
from pinwind.model.builders.urdf_writer import GRAVITY

__all__ = [
    "CARRIER_THICKNESS_FRACTION",
    "GRAVITY",
    "RING_RIM_MODULES",
    "STEEL_DENSITY",
    "EndBody",
    "MassProperties",
    "ParallelStage",
    "PlanetaryStage",
    "StageBearing",
    "StageGear",
    "check_stage_meshes",
    "compound_planetary_urdf",
    "cylinder_inertia",
    "parallel_urdf",
    "planetary_urdf",
    "read_stage_file",
    "shift_sum_for_centre_distance",
    "solid_shaft_stiffness",
    "split_shaft_pair_urdf",
    "stages_urdf",
    "steel_cylinder",
    "write_planetary",
]
