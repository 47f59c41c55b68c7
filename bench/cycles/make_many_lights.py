#!/usr/bin/python3
"""Writes bench/cycles/many_lights.toml: 200 small emissive spheres (radius 0.04, radiance 40 in
six colours) scattered 0.1-1.2 above the grey ground among three diffuse boxes, no sky: the many-
lights scene of issue 38's suite. Deterministic (a fixed linear congruential sequence, no
library), so the file is reproducible: `bench/cycles/make_many_lights.py > many_lights.toml`."""

state = 12345


def rand():
    global state
    state = (1103515245 * state + 12345) % 2**31
    return state / 2**31


COLOURS = [(1, 0.3, 0.2), (0.2, 1, 0.3), (0.3, 0.4, 1), (1, 0.9, 0.4), (1, 1, 1), (0.8, 0.3, 1)]
print(__doc__.replace('"""', "").strip().replace("\n", "\n# ").join(["# ", ""]))
print("""[image]
width = 160
height = 120

[render]
integrator = "path"
max_depth = 8

[camera]
preset = "perspective"
look_from = [0.0, 2.2, 4.5]
look_at = [0.0, 0.2, 0.0]
fov = 45.0
fov_axis = "vertical"

[[material]]
name = "grey"
color = 0.5
""")
for c, rgb in enumerate(COLOURS):
    print(f"""[[material]]
name = "lamp{c}"
color = 0
emission = [{rgb[0]}, {rgb[1]}, {rgb[2]}]
emission_strength = 40
""")
for x, z, s in ((-1.0, -0.5, 0.5), (0.6, 0.3, 0.35), (0.1, -1.3, 0.6)):
    print(f"""[[object]]
type = "box"
min = [{x - s}, 0.0, {z - s}]
max = [{x + s}, {2 * s}, {z + s}]
material = "grey"
""")
for i in range(200):
    x, z, y = -3 + 6 * rand(), -3 + 6 * rand(), 0.1 + 1.1 * rand()
    print(f"""[[object]]
type = "sphere"
center = [{x:.4f}, {y:.4f}, {z:.4f}]
radius = 0.04
material = "lamp{i % len(COLOURS)}"
""")
print("""[[object]]
type = "mesh"
file = "ground.obj"
material = "grey\"""")
