"""carl-bench's dm_control helpers in carl_spec.compat: adapt_context (no dm_control needed), the
shipped XML (equal to dm_control's when it is installed) and the functions that build dm_control
environments (real with dm_control, a clear ImportError without it).

scripts/compare_adapt_context.py checks adapt_context against carl-bench's own over random contexts.
"""

from __future__ import annotations

import importlib.util
import xml.etree.ElementTree as ET
from typing import Any

import numpy as np
import pytest

from carl_spec.compat.context.selection import RandomSelector
from carl_spec.compat.envs.dmc import CARLDmcFingerEnv, CARLDmcFishEnv, CARLDmcPointMassEnv, CARLDmcWalkerEnv
from carl_spec.compat.envs.dmc.carl_dmcontrol import CARLDmcEnv
from carl_spec.compat.envs.dmc.dmc_tasks import _dm_control, finger, fish, pointmass, quadruped, walker
from carl_spec.compat.envs.dmc.dmc_tasks.utils import adapt_context
from carl_spec.compat.envs.dmc.loader import load_dm_control_env
from carl_spec.compat.envs.dmc.wrappers import MujocoToGymWrapper

HAVE_DM_CONTROL = importlib.util.find_spec("dm_control") is not None
needs_dm_control = pytest.mark.skipif(not HAVE_DM_CONTROL, reason=f"dm_control is not installed ({_dm_control.INSTALL})")


def _find(xml: bytes, path: str) -> ET.Element:
    element = ET.fromstring(xml).find(path)
    assert element is not None, path
    return element


# -- adapt_context ------------------------------------------------------------------------------


def test_adapt_context_scales_what_the_model_sets() -> None:
    xml, _ = walker.get_model_and_assets()
    out = adapt_context(
        xml,
        {"joint_damping": 2.0, "friction_tangential": 2.0, "friction_torsional": 1.0, "friction_rolling": 0.5,
         "actuator_strength": 3.0, "gravity": 5.0, "wind_x": 1, "wind_y": 2, "wind_z": 3, "timestep": 0.01,
         "density": 1.2, "viscosity": 0.1},
    )
    assert isinstance(out, bytes)
    assert _find(out, "./default/joint").get("damping") == "0.2"  # walker.xml: .1
    assert _find(out, "./default/geom").get("friction") == "1.4 0.1 0.05"  # walker.xml: .7 .1 .1
    assert _find(out, ".//motor[@name='right_hip']").get("gear") == "300.0"  # walker.xml: 100
    option = _find(out, ".//option")
    assert option.get("gravity") == "0 0 -5.0"
    assert option.get("wind") == "1 2 3"
    assert (option.get("timestep"), option.get("density"), option.get("viscosity")) == ("0.01", "1.2", "0.1")


def test_adapt_context_empty_context_keeps_the_model() -> None:
    xml, _ = walker.get_model_and_assets()
    before = ET.fromstring(xml)
    after = ET.fromstring(adapt_context(xml, {}))
    assert [(e.tag, e.attrib) for e in before.iter()] == [(e.tag, e.attrib) for e in after.iter()]


def test_adapt_context_partial_friction_is_ignored_and_str_input_works() -> None:
    xml, _ = walker.get_model_and_assets()
    out = adapt_context(xml.decode(), {"friction_tangential": 5.0})
    assert _find(out, "./default/geom").get("friction") == ".7 .1 .1"


def test_adapt_context_keeps_carl_bench_bugs() -> None:
    # documented in adapt_context's docstring and docs/guides/migration.md
    fish_xml, _ = fish.get_model_and_assets()
    out = adapt_context(fish_xml, {"joint_stiffness": 1.0, "joint_damping": 1.0})
    added = ET.fromstring(out).find("./default")
    assert added is not None
    assert [c.tag for c in added][:3] == ["general", "geom", "joint"]  # carl-bench inserts after the first
    assert _find(out, "./default/joint").attrib == {"damping": "0.1", "stiffness": "1.0"}
    pm_xml, _ = pointmass.get_model_and_assets()
    gears = [m.get("gear") for m in ET.fromstring(adapt_context(pm_xml, {"actuator_strength": 1.0})).iter("motor")]
    assert gears == [".1", "1.0", "1.0"]  # the default class's .1 is overridden by 1 * factor
    with pytest.raises(TypeError, match="top-level <default>"):
        adapt_context(b"<mujoco><worldbody/></mujoco>", {"gravity": 1.0})


# -- the shipped XML ------------------------------------------------------------------------------


def test_shipped_models_compile_references() -> None:
    assert finger.get_model_and_assets()[1].keys() == {"./common/materials.xml", "./common/skybox.xml", "./common/visual.xml"}
    default = ET.fromstring(finger.get_finger_xml_string())
    assert default.find(".//geom[@name='cap1']").get("fromto") == "0.02 0 -0.09 0.04 0 0.09"  # type: ignore[union-attr]
    with pytest.raises(ValueError, match="Finger cannot reach spinner"):
        finger.get_finger_xml_string(spinner_length=0.1)


@needs_dm_control
def test_shipped_xml_is_dm_controls() -> None:
    from dm_control.suite import common

    assert finger.get_model_and_assets() == (common.read_model("finger.xml"), common.ASSETS)
    assert fish.get_model_and_assets() == (common.read_model("fish.xml"), common.ASSETS)
    assert walker.get_model_and_assets() == (common.read_model("walker.xml"), common.ASSETS)
    assert pointmass.get_model_and_assets() == (common.read_model("point_mass.xml"), common.ASSETS)
    assert quadruped.QUADRUPED_XML.encode() == common.read_model("quadruped.xml")


# -- the functions that build dm_control environments --------------------------------------------

FACTORIES = [
    (finger.spin_context, "CARLDmcFingerEnv"),
    (finger.turn_easy_context, "CARLDmcFingerEnv"),
    (finger.turn_hard_context, "CARLDmcFingerEnv"),
    (fish.upright_context, "CARLDmcFishEnv"),
    (fish.swim_context, "CARLDmcFishEnv"),
    (walker.stand_context, "CARLDmcWalkerEnv"),
    (walker.walk_context, "CARLDmcWalkerEnv"),
    (walker.run_context, "CARLDmcWalkerEnv"),
    (quadruped.walk_context, "CARLDmcQuadrupedEnv"),
    (quadruped.run_context, "CARLDmcQuadrupedEnv"),
    (quadruped.escape_context, "carl-spec has no quadruped escape task"),
    (quadruped.fetch_context, "carl-spec has no quadruped fetch task"),
    (pointmass.easy_pointmass, "CARLDmcPointMassEnv"),
    (pointmass.hard_pointmass, "CARLDmcPointMassEnv"),
]


class _Walker(CARLDmcEnv):
    domain = "walker"
    task = "walk_context"
    get_context_features = staticmethod(CARLDmcWalkerEnv.get_context_features)  # type: ignore[assignment]


@pytest.mark.parametrize(("factory", "instead"), FACTORIES, ids=lambda f: getattr(f, "__name__", ""))
def test_without_dm_control_the_factories_name_the_install_and_the_class(
    factory: Any, instead: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(_dm_control, "available", lambda: False)
    with pytest.raises(ImportError, match=r"pip install dm_control==1\.0\.50 'mujoco<4'") as err:
        factory()
    assert isinstance(err.value, _dm_control.DmControlMissingError)
    assert instead in str(err.value)


def test_without_dm_control_the_wrappers_name_the_install(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(_dm_control, "available", lambda: False)
    for build in (lambda: _Walker(), lambda: MujocoToGymWrapper(None), lambda: load_dm_control_env("walker", "walk")):
        with pytest.raises(_dm_control.DmControlMissingError, match="dm_control==1.0.50"):
            build()


@needs_dm_control
@pytest.mark.parametrize(("factory", "instead"), FACTORIES, ids=lambda f: getattr(f, "__name__", ""))
def test_with_dm_control_the_factories_build_dm_control_environments(factory: Any, instead: str) -> None:
    cls = {"CARLDmcFingerEnv": CARLDmcFingerEnv, "CARLDmcFishEnv": CARLDmcFishEnv, "CARLDmcPointMassEnv": CARLDmcPointMassEnv}
    context = cls[instead].get_default_context() if instead in cls else {"gravity": 9.81}
    context["joint_stiffness"] = 0.0  # carl-bench's default (adapt_context's docstring: 1 blows the fish up)
    for ctx in ({}, context):
        env = factory(context=ctx, random=0)
        env.reset()
        spec = env.action_spec()
        step = env.step(np.zeros(spec.shape, dtype=spec.dtype))
        assert np.isfinite(step.reward)


@needs_dm_control
def test_with_dm_control_carl_dmc_env_runs_contexts() -> None:
    env = _Walker(contexts={0: {"gravity": 5.0}, 1: {"gravity": 15.0}}, obs_context_features=["gravity"])
    obs, info = env.reset(seed=0)
    assert env.observation_space["obs"].contains(obs["obs"].astype(env.observation_space["obs"].dtype))
    first = info["context_id"]
    assert float(obs["context"]["gravity"][0]) == env.context["gravity"]
    assert env.env.env.physics.model.opt.gravity[2] == -env.context["gravity"]
    env.step(env.action_space.sample())
    _, info2 = env.reset()
    assert info2["context_id"] != first
    assert env.env.env.physics.model.opt.gravity[2] == -env.context["gravity"]
    picked = _Walker(contexts={0: {"gravity": 5.0}, 1: {"gravity": 15.0}}, context_selector=RandomSelector)
    ids = {picked.reset(seed=s)[1]["context_id"] for s in range(8)}
    assert ids == {0, 1}
