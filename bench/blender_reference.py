# blender_reference.py — renders a scene exported by vlf_export_scene (bench/export_scene.cpp)
# with Blender's Cycles, an independent path tracer, as a linear EXR to compare with VLF's
# images (walkthrough --reference). Run by Blender:
#   blender -b --factory-startup --python bench/blender_reference.py -- \
#       SCENE.json OUT.exr [--camera NAME] [--size WxH] [--spp N] [--seed S]
#       [--shadow-caustics on|off] [--point-radius R]
# The mapping (units as VLF's: radiance W m^-2 sr^-1, one Blender unit = one scene unit):
#   diffuse rho_d        Diffuse BSDF of colour rho_d
#   mirror rho_s         Glossy BSDF, sharp, of colour rho_s (no Fresnel: an ideal mirror)
#   emission L_e         on a one-sided object that is one planar rectangle (a lamp): a
#                        Cycles area light of that rectangle (one-sided, Lambertian) of power
#                        4 A max(L_e) and colour L_e / max(L_e), a millionth of the scene's
#                        size in front of the object, which keeps the rest of its material
#                        and shows L_e to camera rays only
#                        (Cycles' area light of power P has radiance P / 4A: checked against
#                        the closed form of a small lamp over a floor to 0.06 %);
#                        otherwise Emission of colour L_e, strength 1 (radiance L_e), black
#                        from behind by a Mix by Backfacing (in Cycles that emitter leaves
#                        the walls near a ceiling lamp about 1 % darker than VLF and than
#                        the area light, BENCHMARKS.md "Against Blender Cycles")
#   one-sided faces      black from behind (a Mix by Backfacing), as VLF's backs absorb
#   dielectric n, sigma  Glass BSDF, sharp, IOR n; Volume Absorption of density max(sigma)
#                        and colour 1 - sigma / max(sigma) (Cycles absorbs density x
#                        (1 - colour) per unit length)
#   point light I        Point light of power 4 pi I, radius 0 (Cycles' point light sends
#                        power / (4 pi) per steradian; bench/blender_point_check.json checks it)
#                        or R (--point-radius: a small sphere that eye paths through glass or
#                        mirrors can hit, so Cycles' path tracing finds the caustic, noisily;
#                        not seen by camera rays in Cycles 3.4, but seen in mirrors and
#                        through glass, where VLF shows no point light: a few bright pixels;
#                        Cycles 3.4's light nodes cannot tell such a path from light sampling)
#   --shadow-caustics on Cycles' manifold next-event estimation (MNEE, Blender 3.2+): glass
#                        objects cast shadow caustics of point lights, the others receive them.
#                        It finds one refracted path per sample (where several paths through
#                        the glass reach a point it misses the others) and no reflection
#                        off the glass, so it is a lower bound of the caustic
#   directional E        Sun of strength E, angle = the angular diameter
#   spot light I         the point light above, its strength VLF's falloff smoothstep(cos_outer,
#                        cos_inner, cos theta) by light nodes (Cycles' spot lights multiply by
#                        cos theta and blend in angle: not VLF's); bench/blender_spot_check.json
#                        checks it
# No clamping, no glossy blur, no denoising, 1-pixel box filter (a pixel's mean, as VLF's
# images are), bounces up to 256 of every kind, the world black, the view transform
# 'Standard' (the EXR holds scene-linear values).
import json
import math
import os
import sys

import bpy
from mathutils import Matrix, Vector


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    if len(argv) < 2:
        sys.exit("usage: blender -b --python blender_reference.py -- SCENE.json OUT.exr "
                 "[--camera NAME] [--size WxH] [--spp N] [--seed S]")
    opts = {"scene": argv[0], "out": argv[1], "camera": None, "size": (128, 128), "spp": 1024,
            "seed": 0, "shadow_caustics": False, "point_radius": 0.0}
    rest = argv[2:]
    while rest:
        key = rest.pop(0)
        if not rest:
            sys.exit(f"{key}: needs a value")
        value = rest.pop(0)
        if key == "--camera":
            opts["camera"] = value
        elif key == "--size":
            w, h = value.lower().split("x")
            opts["size"] = (int(w), int(h))
        elif key == "--spp":
            opts["spp"] = int(value)
        elif key == "--seed":
            opts["seed"] = int(value)
        elif key == "--shadow-caustics":
            if value not in ("on", "off"):
                sys.exit(f"--shadow-caustics: on or off, not '{value}'")
            opts["shadow_caustics"] = value == "on"
        elif key == "--point-radius":
            opts["point_radius"] = float(value)
            if not opts["point_radius"] >= 0:
                sys.exit(f"--point-radius: a radius of at least 0, not '{value}'")
        else:
            sys.exit(f"{key}: unknown option")
    return opts


def node_material(name, m, one_sided, camera_emission=None):
    """The material's node tree; `camera_emission`: a radiance that only camera rays see
    (a lamp whose light an area light sends: the camera sees the lamp, nothing else does)."""
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nt = mat.node_tree
    for n in list(nt.nodes):
        nt.nodes.remove(n)
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    if m["dielectric"]:
        glass = nt.nodes.new("ShaderNodeBsdfGlass")
        glass.distribution = "SHARP"
        glass.inputs["Color"].default_value = (1, 1, 1, 1)
        glass.inputs["IOR"].default_value = m["ior"]
        nt.links.new(glass.outputs[0], out.inputs["Surface"])
        sigma = m["absorption"]
        top = max(sigma)
        if top > 0:
            vol = nt.nodes.new("ShaderNodeVolumeAbsorption")
            vol.inputs["Density"].default_value = top
            vol.inputs["Color"].default_value = tuple(1 - s / top for s in sigma) + (1,)
            nt.links.new(vol.outputs[0], out.inputs["Volume"])
        return mat
    shader = None

    def add(s):
        nonlocal shader
        if shader is None:
            shader = s
        else:
            a = nt.nodes.new("ShaderNodeAddShader")
            nt.links.new(shader.outputs[0], a.inputs[0])
            nt.links.new(s.outputs[0], a.inputs[1])
            shader = a

    if max(m["diffuse"]) > 0:
        d = nt.nodes.new("ShaderNodeBsdfDiffuse")
        d.inputs["Color"].default_value = tuple(m["diffuse"]) + (1,)
        d.inputs["Roughness"].default_value = 0.0
        add(d)
    if max(m["specular"]) > 0:
        g = nt.nodes.new("ShaderNodeBsdfGlossy")
        g.distribution = "SHARP"
        g.inputs["Color"].default_value = tuple(m["specular"]) + (1,)
        add(g)
    if max(m["emission"]) > 0:
        e = nt.nodes.new("ShaderNodeEmission")
        e.inputs["Color"].default_value = tuple(m["emission"]) + (1,)
        e.inputs["Strength"].default_value = 1.0
        add(e)
    if camera_emission is not None:
        e = nt.nodes.new("ShaderNodeEmission")
        e.inputs["Color"].default_value = tuple(camera_emission) + (1,)
        path = nt.nodes.new("ShaderNodeLightPath")
        nt.links.new(path.outputs["Is Camera Ray"], e.inputs["Strength"])
        add(e)
        mat.cycles.sample_as_light = False  # its light is the area light's
    if shader is None:  # black
        d = nt.nodes.new("ShaderNodeBsdfDiffuse")
        d.inputs["Color"].default_value = (0, 0, 0, 1)
        shader = d
    if one_sided:
        black = nt.nodes.new("ShaderNodeBsdfDiffuse")
        black.inputs["Color"].default_value = (0, 0, 0, 1)
        geo = nt.nodes.new("ShaderNodeNewGeometry")
        mix = nt.nodes.new("ShaderNodeMixShader")
        nt.links.new(geo.outputs["Backfacing"], mix.inputs["Fac"])
        nt.links.new(shader.outputs[0], mix.inputs[1])
        nt.links.new(black.outputs[0], mix.inputs[2])
        shader = mix
    nt.links.new(shader.outputs[0], out.inputs["Surface"])
    return mat


def _sub(a, b):
    return [a[0] - b[0], a[1] - b[1], a[2] - b[2]]


def _dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def _cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def _unit(a):
    n = math.sqrt(_dot(a, a))
    return [x / n for x in a]


def rectangle_of(obj):
    """(centre, u, v, normal, size_u, size_v) of the rectangle that the object's faces tile,
    when they lie in one plane and fill their bounding rectangle there; else None. In double
    precision (mathutils is single)."""
    vs = obj["vertices"]
    area_vector = [0.0, 0.0, 0.0]
    for f in obj["faces"]:
        for k in range(1, len(f) - 1):
            c = _cross(_sub(vs[f[k]], vs[f[0]]), _sub(vs[f[k + 1]], vs[f[0]]))
            area_vector = [area_vector[i] + c[i] / 2 for i in range(3)]
    area = math.sqrt(_dot(area_vector, area_vector))
    if area <= 0:
        return None
    normal = [x / area for x in area_vector]
    first = obj["faces"][0]
    u = _sub(vs[first[1]], vs[first[0]])
    u = _unit(_sub(u, [normal[i] * _dot(u, normal) for i in range(3)]))
    v = _cross(normal, u)
    centre = [sum(p[i] for p in vs) / len(vs) for i in range(3)]
    size = max(math.sqrt(_dot(_sub(p, centre), _sub(p, centre))) for p in vs)
    if any(abs(_dot(_sub(p, centre), normal)) > 1e-9 * size for p in vs):
        return None
    us = [_dot(_sub(p, centre), u) for p in vs]
    ws = [_dot(_sub(p, centre), v) for p in vs]
    su, sv = max(us) - min(us), max(ws) - min(ws)
    if abs(su * sv - area) > 1e-9 * area:
        return None
    mu, mw = (max(us) + min(us)) / 2, (max(ws) + min(ws)) / 2
    middle = [centre[i] + u[i] * mu + v[i] * mw for i in range(3)]
    return Vector(middle), Vector(u), Vector(v), Vector(normal), su, sv


def area_light(name, rect, emission, offset):
    """A Cycles area light on `rect` (rectangle_of) of radiance `emission`, `offset` in front."""
    centre, u, v, normal, su, sv = rect
    top = max(emission)
    data = bpy.data.lights.new(name, "AREA")
    data.shape = "RECTANGLE"
    data.size, data.size_y = su, sv
    data.energy = 4.0 * su * sv * top  # Cycles: radiance = power / (4 A)
    data.color = tuple(e / top for e in emission)
    ob = bpy.data.objects.new(name, data)
    # An area light shines along its local -Z.
    basis = Matrix(((u.x, v.x, -normal.x, 0), (u.y, v.y, -normal.y, 0),
                    (u.z, v.z, -normal.z, 0), (0, 0, 0, 1)))
    ob.matrix_world = Matrix.Translation(centre + normal * offset) @ basis
    return ob


def spot_profile(data, light):
    """VLF's spot falloff, smoothstep(cos_outer, cos_inner, cos theta), as the strength of
    the point light `data`'s emission: cos theta is the light's local -Z (its axis) dotted
    with the object-space direction to the lit point (the Normal of the light's texture
    coordinates), smoothstepped by a Map Range node. (Cycles' own spot lights multiply by
    cos theta and blend in angle; its IES node scales a profile by a factor of its own.)"""
    data.use_nodes = True
    nt = data.node_tree
    coords = nt.nodes.new("ShaderNodeTexCoord")
    dot = nt.nodes.new("ShaderNodeVectorMath")
    dot.operation = "DOT_PRODUCT"
    dot.inputs[1].default_value = (0.0, 0.0, -1.0)
    nt.links.new(coords.outputs["Normal"], dot.inputs[0])
    ramp = nt.nodes.new("ShaderNodeMapRange")
    ramp.interpolation_type = "SMOOTHSTEP"
    ramp.clamp = True
    ramp.inputs["From Min"].default_value = light["cos_outer"]
    ramp.inputs["From Max"].default_value = light["cos_inner"]
    ramp.inputs["To Min"].default_value = 0.0
    ramp.inputs["To Max"].default_value = 1.0
    nt.links.new(dot.outputs["Value"], ramp.inputs["Value"])
    emission = next(n for n in nt.nodes if n.type == "EMISSION")
    nt.links.new(ramp.outputs["Result"], emission.inputs["Strength"])


def look_matrix(eye, target, up):
    eye, target, up = Vector(eye), Vector(target), Vector(up)
    z = (eye - target).normalized()  # a Blender camera looks along its -Z
    x = up.cross(z).normalized()
    y = z.cross(x)
    return Matrix(((x.x, y.x, z.x, eye.x), (x.y, y.y, z.y, eye.y), (x.z, y.z, z.z, eye.z),
                   (0, 0, 0, 1)))


def main():
    opts = parse_args()
    with open(opts["scene"]) as f:
        scene_json = json.load(f)
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene

    points = [v for obj in scene_json.get("objects", []) for v in obj["vertices"]]
    extent = max(math.dist(p, points[0]) for p in points) if points else 1.0
    materials = {}
    for obj in scene_json.get("objects", []):
        m = scene_json["materials"][obj["material"]]
        rect = None
        if max(m["emission"]) > 0 and not obj["two_sided"] and not m["dielectric"]:
            rect = rectangle_of(obj)
        camera_emission = None
        if rect is not None:
            light = area_light(obj["name"] + " (area light)", rect, m["emission"],
                               1e-6 * extent)
            scene.collection.objects.link(light)
            camera_emission = m["emission"]
            m = dict(m, emission=[0.0, 0.0, 0.0])
        key = (obj["material"], obj["two_sided"], rect is not None)
        if key not in materials:
            materials[key] = node_material(f"{m['name']}#{len(materials)}", m,
                                           one_sided=not obj["two_sided"],
                                           camera_emission=camera_emission)
        mesh = bpy.data.meshes.new(obj["name"])
        mesh.from_pydata([tuple(v) for v in obj["vertices"]], [], obj["faces"])
        mesh.update()
        if "corner_normals" in obj:
            mesh.use_auto_smooth = True
            loop_normals = []
            for poly in mesh.polygons:
                corners = obj["corner_normals"][poly.index]
                for k in range(poly.loop_total):
                    loop_normals.append(tuple(corners[k]))
            for poly in mesh.polygons:
                poly.use_smooth = True
            mesh.normals_split_custom_set(loop_normals)
        mesh.materials.append(materials[key])
        ob = bpy.data.objects.new(obj["name"], mesh)
        if opts["shadow_caustics"]:
            ob.cycles.is_caustics_caster = bool(m["dielectric"])
            ob.cycles.is_caustics_receiver = not m["dielectric"]
        scene.collection.objects.link(ob)

    for light in scene_json.get("lights", []):
        kind = light["type"]
        if kind in ("point", "spot"):
            data = bpy.data.lights.new(light["name"], "POINT")
            top = max(light["intensity"])
            data.energy = 4 * math.pi * top
            data.color = tuple(i / top for i in light["intensity"]) if top > 0 else (0, 0, 0)
            data.shadow_soft_size = opts["point_radius"]
            data.cycles.is_caustics_light = opts["shadow_caustics"]
            ob = bpy.data.objects.new(light["name"], data)
            ob.location = light["position"]
            if kind == "spot":
                spot_profile(data, light)
                d = Vector(light["direction"]).normalized()
                ob.rotation_mode = "QUATERNION"
                ob.rotation_quaternion = (-d).to_track_quat("Z", "Y")  # its axis: local -Z
        else:
            data = bpy.data.lights.new(light["name"], "SUN")
            top = max(light["irradiance"])
            data.energy = top
            data.color = tuple(e / top for e in light["irradiance"]) if top > 0 else (0, 0, 0)
            data.angle = math.radians(light["angular_diameter_deg"])
            ob = bpy.data.objects.new(light["name"], data)
            d = Vector(light["direction"]).normalized()
            ob.rotation_mode = "QUATERNION"
            ob.rotation_quaternion = (-d).to_track_quat("Z", "Y")  # a sun shines along -Z
        scene.collection.objects.link(ob)

    cams = scene_json.get("cameras", [])
    if not cams:
        sys.exit(f"{opts['scene']}: no camera")
    cam = cams[0] if opts["camera"] is None else next(
        (c for c in cams if c["name"] == opts["camera"]), None)
    if cam is None:
        sys.exit(f"{opts['scene']}: no camera '{opts['camera']}'")
    cdata = bpy.data.cameras.new("camera")
    cdata.sensor_fit = "VERTICAL"
    cdata.angle_y = math.radians(cam["fov_y_deg"])
    cdata.clip_start = 1e-4
    cdata.clip_end = 1e7
    cob = bpy.data.objects.new("camera", cdata)
    cob.matrix_world = look_matrix(cam["eye"], cam["look_at"], cam["up"])
    scene.collection.objects.link(cob)
    scene.camera = cob

    world = bpy.data.worlds.new("black")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0
    scene.world = world

    scene.render.engine = "CYCLES"
    c = scene.cycles
    c.device = "CPU"
    scene.render.threads_mode = "FIXED"
    scene.render.threads = os.cpu_count() or 1
    c.samples = opts["spp"]
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.seed = opts["seed"]
    c.max_bounces = 256
    c.diffuse_bounces = 256
    c.glossy_bounces = 256
    c.transmission_bounces = 256
    c.transparent_max_bounces = 256
    c.volume_bounces = 256
    c.sample_clamp_direct = 0.0
    c.sample_clamp_indirect = 0.0
    c.blur_glossy = 0.0
    c.caustics_reflective = True
    c.caustics_refractive = True
    c.pixel_filter_type = "BOX"
    c.filter_width = 1.0
    scene.render.resolution_x, scene.render.resolution_y = opts["size"]
    scene.render.resolution_percentage = 100
    scene.render.film_transparent = False
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.view_settings.exposure = 0.0
    scene.view_settings.gamma = 1.0
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_depth = "32"
    scene.render.image_settings.color_mode = "RGB"
    scene.render.filepath = opts["out"]
    scene.render.use_file_extension = False
    bpy.ops.render.render(write_still=True)


main()
