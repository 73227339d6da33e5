"""dm_control 1.0.50's `suite/common/*.xml` (Apache-2.0, the dm_control authors), verbatim: the
assets (`dm_control.suite.common.ASSETS`) the suite's XML includes, keyed as dm_control keys them."""

MATERIALS_XML = """<!--
Common textures, colors and materials to be used throughout this suite. Some
materials such as xxx_highlight are activated on occurence of certain events,
for example receiving a positive reward.
-->
<mujoco>
  <asset>
    <texture name="grid" type="2d" builtin="checker" rgb1=".1 .2 .3" rgb2=".2 .3 .4" width="300" height="300" mark="edge" markrgb=".2 .3 .4"/>
    <material name="grid" texture="grid" texrepeat="1 1" texuniform="true" reflectance=".2"/>
    <material name="self" rgba=".7 .5 .3 1"/>
    <material name="self_default" rgba=".7 .5 .3 1"/>
    <material name="self_highlight" rgba="0 .5 .3 1"/>
    <material name="effector" rgba=".7 .4 .2 1"/>
    <material name="effector_default" rgba=".7 .4 .2 1"/>
    <material name="effector_highlight" rgba="0 .5 .3 1"/>
    <material name="decoration" rgba=".3 .5 .7 1"/>
    <material name="eye" rgba="0 .2 1 1"/>
    <material name="target" rgba=".6 .3 .3 1"/>
    <material name="target_default" rgba=".6 .3 .3 1"/>
    <material name="target_highlight" rgba=".6 .3 .3 .4"/>
    <material name="site" rgba=".5 .5 .5 .3"/>
  </asset>
</mujoco>
"""

SKYBOX_XML = """<mujoco>
  <asset>
      <texture name="skybox" type="skybox" builtin="gradient" rgb1=".4 .6 .8" rgb2="0 0 0"
               width="800" height="800" mark="random" markrgb="1 1 1"/>
  </asset>
</mujoco>
"""

VISUAL_XML = """<mujoco>
  <visual>
    <headlight ambient=".4 .4 .4" diffuse=".8 .8 .8" specular="0.1 0.1 0.1"/>
    <map znear=".01"/>
    <quality shadowsize="2048"/>
  </visual>
</mujoco>
"""

#: dm_control's `common.ASSETS`: file name (as the XML includes it) -> contents
ASSETS: dict[str, bytes] = {
    "./common/materials.xml": MATERIALS_XML.encode(),
    "./common/skybox.xml": SKYBOX_XML.encode(),
    "./common/visual.xml": VISUAL_XML.encode(),
}
