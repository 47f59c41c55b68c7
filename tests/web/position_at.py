"""The position AOV of one pixel of a scene, rendered at its own size with one sample at each
pixel's center: what the editor's coin must land on. Usage: position_at.py SCENE X Y"""
import json
import sys

import anamorph

scene = anamorph.load(sys.argv[1], set={"render.antialias": "uniform"})
out = scene.render(spp=1, sampler="center", aovs=["position"])
x, y = int(sys.argv[2]), int(sys.argv[3])
print(json.dumps([float(c) for c in out["position"][y, x, :3]]))
