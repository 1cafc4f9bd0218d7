#!/usr/bin/env python3
# scene_schema_test.py — docs/scene.schema.json against the scene loader: every shipped scene
# (scenes/, scenes/complexity/, tests/scenes/) validates, and a set of broken scenes is
# rejected by the schema *and* by the loader (propagate --dry-run), the loader naming the
# same JSON place. Needs python3-jsonschema (scripts/install-deps.sh).
#   scene_schema_test.py SOURCE_DIR PROPAGATE WORK_DIR
import copy
import glob
import json
import os
import subprocess
import sys

try:
    import jsonschema
except ImportError:
    sys.exit("scene_schema_test: python3-jsonschema is missing (run scripts/install-deps.sh)")

source_dir, propagate, work_dir = sys.argv[1:4]
os.makedirs(work_dir, exist_ok=True)
with open(os.path.join(source_dir, "docs", "scene.schema.json")) as f:
    schema = json.load(f)
jsonschema.Draft202012Validator.check_schema(schema)
validator = jsonschema.Draft202012Validator(schema)
failures = []

# ---- every shipped scene is valid ---------------------------------------------------------
scenes = []
for pattern in ("scenes/*.json", "scenes/complexity/*.json", "tests/scenes/*.json"):
    scenes += sorted(glob.glob(os.path.join(source_dir, pattern)))
if len(scenes) < 10:
    failures.append(f"found only {len(scenes)} scenes under {source_dir}")
for path in scenes:
    with open(path) as f:
        scene = json.load(f)
    for e in validator.iter_errors(scene):
        failures.append(f"{os.path.relpath(path, source_dir)}: {e.json_path}: {e.message}")

# ---- broken scenes: the schema and the loader both refuse them -----------------------------
# A small valid scene; each case breaks one thing. (path in the loader's message, edit)
BASE = {
    "$schema": "../docs/scene.schema.json",
    "materials": {"white": {"diffuse": [0.5, 0.5, 0.5]},
                  "lamp": {"diffuse": [0.5, 0.5, 0.5], "emission": [4, 4, 4]}},
    "objects": [
        {"type": "box", "min": [0, 0, 0], "max": [1, 1, 1], "flip": True, "material": "white"},
        {"type": "polygon", "material": "lamp",
         "vertices": [[0.4, 0.99, 0.4], [0.6, 0.99, 0.4], [0.6, 0.99, 0.6], [0.4, 0.99, 0.6]]},
        {"type": "sphere", "center": [0.5, 0.3, 0.5], "radius": 0.2, "material": "white"},
        {"type": "cylinder", "radius": 0.1, "height": 0.3, "center": [0.2, 0, 0.2],
         "material": "white"},
    ],
    "cameras": [{"name": "c", "eye": [0.5, 0.5, 0.05], "look_at": [0.5, 0.5, 1], "fov_y_deg": 60}],
    "lights": [
        {"name": "bulb", "type": "point", "position": [0.5, 0.8, 0.5], "power": [10, 10, 10]},
        {"type": "spot", "position": [0.2, 0.9, 0.2], "direction": [0, -1, 0], "inner_deg": 10,
         "outer_deg": 30, "intensity": [1, 1, 1]},
        {"type": "directional", "direction": [0, -1, -1], "irradiance": [2, 2, 2],
         "angular_diameter_deg": 0.53},
    ],
    "settings": {"texel_size": 0.1, "units": "m"},
}


def broken(edit):
    s = copy.deepcopy(BASE)
    edit(s)
    return s


CASES = [
    ("colour", lambda s: s.update(colour=1)),
    ("materials.white.glossy", lambda s: s["materials"]["white"].update(glossy=0.5)),
    ("materials.white.diffuse[1]", lambda s: s["materials"]["white"].update(diffuse=[0.5, 1.5, 0.5])),
    ("materials.lamp.emission[0]", lambda s: s["materials"]["lamp"].update(emission=[-1, 1, 1])),
    ("materials.white.diffuse", lambda s: s["materials"]["white"].update(dielectric={"ior": 1.5})),
    ("materials.glass.dielectric.ior",
     lambda s: s["materials"].update(glass={"dielectric": {"ior": 1.0}})),
    ("materials.glass.dielectric.absorption[2]",
     lambda s: s["materials"].update(glass={"dielectric": {"ior": 1.5, "absorption": [0, 0, -1]}})),
    ("objects", lambda s: s.update(objects=[])),
    ("objects[0].radius", lambda s: s["objects"][0].update(radius=1)),
    ("objects[0].min", lambda s: s["objects"][0].update(min=[0, 0])),
    ("objects[2].type", lambda s: s["objects"][2].update(type="cone")),
    ("objects[2].radius", lambda s: s["objects"][2].update(radius="big")),
    ("objects[2].subdivisions", lambda s: s["objects"][2].update(subdivisions=7)),
    ("objects[2].subdivisions", lambda s: s["objects"][2].update(subdivisions=2.5)),
    ("objects[3].segments", lambda s: s["objects"][3].update(segments=2)),
    ("objects[3].vertices", lambda s: s["objects"][3].update(vertices=[[0, 0, 0]])),
    ("objects[1].vertices", lambda s: s["objects"][1].update(vertices=[[0, 0, 0], [1, 0, 0]])),
    ("objects[1].triangulate", lambda s: s["objects"][1].update(triangulate="yes")),
    ("objects[0].flip", lambda s: s["objects"][0].update(flip=1)),
    ("objects[0].scale", lambda s: s["objects"][0].update(scale=0)),
    ("objects[0].scale[2]", lambda s: s["objects"][0].update(scale=[1, 1, -1])),
    ("objects[0].translate", lambda s: s["objects"][0].update(translate=[1, 2])),
    ("(top level)", lambda s: s["objects"][0].pop("material")),
    ("objects[0].material", lambda s: s["objects"][0].update(material=3)),
    ("objects[2].file", lambda s: s["objects"].__setitem__(
        2, {"type": "mesh", "file": "meshes/ring.dae", "material": "white"})),
    ("cameras[0].zoom", lambda s: s["cameras"][0].update(zoom=2)),
    ("cameras[0].fov_y_deg", lambda s: s["cameras"][0].update(fov_y_deg=180)),
    ("cameras[0]", lambda s: s["cameras"][0].pop("eye")),
    ("settings.texel_size", lambda s: s["settings"].update(texel_size=0)),
    ("settings.seed", lambda s: s["settings"].update(seed=1)),
    ('["$schema"]', lambda s: s.update({"$schema": 1})),
    ("lights", lambda s: s.update(lights={})),
    ("lights[0].type", lambda s: s["lights"][0].update(type="area")),
    ("lights[0].colour", lambda s: s["lights"][0].update(colour=[1, 1, 1])),
    ("lights[0].intensity", lambda s: s["lights"][0].update(intensity=[1, 1, 1])),
    ("lights[0]", lambda s: s["lights"][0].pop("power")),
    ("lights[0].inner_deg", lambda s: s["lights"][0].update(inner_deg=10)),
    ("lights[0].power[1]", lambda s: s["lights"][0].update(power=[1, -1, 1])),
    ("lights[0].power[2]", lambda s: s["lights"][0].update(power=[1, 1, 1e21])),
    ("lights[0].position[1]", lambda s: s["lights"][0].update(position=[0, 1e16, 0])),
    ("lights[1]", lambda s: s["lights"][1].pop("direction")),
    ("lights[1].direction", lambda s: s["lights"][1].update(direction=[0, 0, 0])),
    ("lights[1].outer_deg", lambda s: s["lights"][1].update(outer_deg=0)),
    ("lights[1].outer_deg", lambda s: s["lights"][1].update(outer_deg=181)),
    ("lights[1].inner_deg", lambda s: s["lights"][1].update(inner_deg=-1)),
    ("lights[2].position", lambda s: s["lights"][2].update(position=[0, 1, 0])),
    ("lights[2].angular_diameter_deg", lambda s: s["lights"][2].update(angular_diameter_deg=31)),
    ("lights[2]", lambda s: s["lights"][2].pop("irradiance")),
]


def loader_error(scene, name):
    path = os.path.join(work_dir, name)
    with open(path, "w") as f:
        json.dump(scene, f, indent=1)
    r = subprocess.run([propagate, path, "--dry-run"], capture_output=True, text=True)
    return r.returncode, r.stderr.strip(), path


# The base scene itself is valid for both (and its "$schema" key is accepted).
if list(validator.iter_errors(BASE)):
    failures.append("the base scene does not validate against the schema")
rc, err, _ = loader_error(BASE, "base.json")
if rc != 0:
    failures.append(f"the loader refuses the base scene: {err}")

for k, (place, edit) in enumerate(CASES):
    scene = broken(edit)
    if not list(validator.iter_errors(scene)):
        failures.append(f"case {k} ({place}): the schema accepts it")
    rc, err, path = loader_error(scene, f"broken-{k}.json")
    if place == "(top level)" and "objects[0]: missing required key 'material'" in err:
        place = "objects[0]"
    want = f"{path}: {place}: "
    if rc != 2 or want not in err:
        failures.append(f"case {k}: the loader says (exit {rc}) {err!r}, expected it to name '{place}'")

for f in failures:
    print("FAIL:", f)
print(f"scene_schema_test: {len(scenes)} scenes, {len(CASES)} broken cases, {len(failures)} failures")
sys.exit(1 if failures else 0)
