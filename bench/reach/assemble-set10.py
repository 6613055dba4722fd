#!/usr/bin/env python3
"""Assembles a tenth reach set (/work/reach-set10) from bare git mirrors of repositories no
earlier set used, with the shared selection of bench/reach/reach_select.py (per source the
sorted mesh files under the listed folders, every k-th over the cap; skipped: files over
30 MB, blobs absent from the snapshot, Git LFS pointers, a blob already taken).
Sources: robot models (RobotLocomotion/models incl. YCB scans, osrf/gazebo_models,
ankurhanda/robot-assets, unitreerobotics/unitree_ros, Farama-Foundation/Gymnasium-Robotics,
Kinovarobotics/ros_kortex), simulation test meshes (ipc-sim/rigid-ipc,
NVIDIAGameWorks/kaolin), a printer benchmark (CreativeTools/3DBenchy) and game assets
(gdquest-demos/godot-4-3d-third-person-controller).
Session 58's helper; writes /work/reach-set10/MANIFEST.tsv (copied to
bench/reach/MANIFEST-set10.tsv).
Usage: python3 bench/reach/assemble-set10.py; then PREPARE=auto COMPARE=none JOBS=1
bench/reach/run.sh build/cli/spheremap /work/reach-set10"""
import sys
sys.path.insert(0, __import__("os").path.dirname(__import__("os").path.abspath(__file__)))
from reach_select import Source, assemble

EXT = r"\.(glb|gltf|obj|off|stl|ply|drc)$"
SOURCES = [
    Source("RobotLocomotion/models", "robotlocomotion-models",
           "no repo licence; a LICENSE per folder: atlas/manipulation_station BSD-3-Clause (RLG), TRI models "
           "(dishes, tri_homecart, veggies, wsg_50) BSD-3-Clause, franka/skydio/realsense Apache-2.0, pr2/ur/allegro BSD "
           "(upstream), iiwa iiwa_stack licence, ycb CC-BY-4.0, tutorials CC0-1.0",
           r"^.*" + EXT, cap=22),
    Source("osrf/gazebo_models", "gazebo_models",
           "CC-BY-3.0 (repo LICENSE, Nathan Koenig)",
           r"^.*" + EXT, cap=18),
    Source("ipc-sim/rigid-ipc", "rigid-ipc",
           "MIT (repo LICENSE); some folders carry their own (meshes/*/LICENSE*.txt: 3DBenchy, octopus, erleben, "
           "screw-and-nut, anchor, chain/sprocket)",
           r"^meshes/.*" + EXT, exclude=r"^meshes/(arch|fracture/wall)/", cap=20),
    Source("ankurhanda/robot-assets", "robot-assets",
           "no repo licence; README lists each robot's upstream repository (Franka, iiwa, Fetch, YuMi, Ginger, "
           "Halodi, NASA R2/Val, Robotiq, Barrett hand, PR2): unknown",
           r"^urdfs/.*" + EXT, exclude=r"^urdfs/robots/ur(5|10)/", cap=20),
    Source("unitreerobotics/unitree_ros", "unitree_ros",
           "BSD-3-Clause (repo LICENSE, Unitree Robotics)",
           r"^robots/.*" + EXT, cap=20),
    Source("Farama-Foundation/Gymnasium-Robotics", "gymnasium-robotics",
           "MIT (repo LICENSE); assets/LICENSE.md: Fetch and ShadowHand adapted by OpenAI, ShadowHand code Apache-2.0 "
           "(Vikash Kumar); kitchen_franka assets Apache-2.0 (DSuite Authors)",
           r"^gymnasium_robotics/envs/assets/.*" + EXT, cap=18),
    Source("Kinovarobotics/ros_kortex", "ros_kortex",
           "BSD-3-Clause (repo LICENSE, Kinova inc.)",
           r"^kortex_description/.*" + EXT, cap=15),
    Source("CreativeTools/3DBenchy", "3DBenchy",
           "unknown (no LICENSE file; README without licence terms)",
           r"^.*" + EXT, cap=8),
    Source("NVIDIAGameWorks/kaolin", "kaolin",
           "Apache-2.0 (repo LICENSE); sample_data/meshes/README.md per model: armchair CC-BY-4.0, avocado and "
           "simple_muscle CC0, fox a TurboSquid model 'research purposes only, may not redistribute', others authored in Blender",
           r"^(examples|sample_data|tests)/.*" + EXT, exclude=r"^tests/samples/(render|rep)/"),  # those are symlinks
    Source("gdquest-demos/godot-4-3d-third-person-controller", "gdquest-tps",
           "code MIT (repo LICENSE, GDQuest); README: assets CC-BY-4.0 (GDQuest)",
           r"^.*" + EXT, cap=16),
]

assemble(SOURCES, "/work/reach-set10", max_bytes=30e6, dedup=True, ignore_case=True)
