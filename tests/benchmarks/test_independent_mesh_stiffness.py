"""Every sample of undamped compliant runs carries the recoded ISO 6336-1 stiffness.

``benchmarks/independent_mesh_stiffness.py`` recodes c′, c_γα, the path of contact and the
stiffness along it from the model file's gear data (docs/validation.md, "Independent recoding
of the mesh stiffness"). Here the Saleh 2017 planetary (spur, ring taken as a rack) and the Cai
spur pair (face widths 15 and 30 mm): the run's F_n over the step's mean deflection equals the
recoded k(x) at the logged contact position, c′b with one pair and 1.75 c′b with two.
"""

from __future__ import annotations

import contextlib

import numpy as np
import pytest

import pinwind
from pinwind.errors import ImplausibleGear
from pinwind.model.compliance import MeshCompliance
from tests.benchmarks import benchmark_module

recoding = benchmark_module("independent_mesh_stiffness.py", "independent_mesh_stiffness")


@pytest.mark.parametrize("name", ["saleh2017_planetary", "cai_spur_pair"])
def test_compliant_run_carries_the_recoded_stiffness_at_every_sample(name):
    r = recoding
    model = r.ROOT / "models" / f"{name}.urdf"
    gears, meshes = r.gears_of(model)
    # the Cai model's gear 2 is lighter than its teeth (its source's inertia, kept)
    light = pytest.warns(ImplausibleGear) if name == "cai_spur_pair" else contextlib.nullcontext()
    with light:
        gb = pinwind.load(model)
    res = pinwind.simulate(
        gb,
        duration=0.01,
        dt=1e-5,
        torques=r.MODELS[name]["torques"],
        initial_speeds=r.MODELS[name]["speeds"],
        meshes={m[0]: MeshCompliance(damping=0.0) for m in meshes},
    )
    for mesh, a, b in meshes:
        rec = r.recode(gears[a], gears[b], ring_as_rack=True)
        path = gb.mesh(mesh).path
        np.testing.assert_allclose(path.contact_ratio, rec["eps_a"], rtol=1e-13)
        np.testing.assert_allclose(path.start_roll_1, rec["s_a"], rtol=1e-13)
        s = res.mesh(mesh)
        f, d, flank = s.normal, s.deflection, s.flank
        nxt = np.append(d[1:], np.nan)
        ok = (d > 1e-9) & (nxt > 1e-9) & np.append(flank[:-1] == flank[1:], False) & (f > 0)
        assert ok.sum() > 300
        k_rec, pairs = r.stiffness_at(rec, s.contact_position[ok] - rec["s_a"])
        assert set(pairs) == {1, 2}
        np.testing.assert_allclose(f[ok] / (0.5 * (d[ok] + nxt[ok])), k_rec, rtol=1e-9)
        np.testing.assert_array_equal(s.pairs[ok], pairs)
