"""anamorph for Blender: a render engine whose camera is anamorph's distortion camera.

The Blender-facing code (every use of bpy) is in bl.py; locate.py finds the anamorph Python
module, schema_props.py turns anamorph's parameter declarations into property descriptions and
scene_toml.py writes the scene file anamorph reads. See docs/blender.md.
"""

bl_info = {
    "name": "anamorph",
    "author": "anamorph developers",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "Render Properties > Render Engine > anamorph; Camera Properties > anamorph",
    "description": "Renders with anamorph: nonlinear cameras, presets and centers of interest",
    "doc_url": "https://example.invalid/anamorph/docs/blender.md",
    "category": "Render",
}


def register():
    from . import bl

    bl.register()


def unregister():
    from . import bl

    bl.unregister()
