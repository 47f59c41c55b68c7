// Every declared key of the camera, image and render tables as data (name, type, default as TOML
// text, range, unit, choices, doc), by table and form: what the editor's panels and the Python
// package's keyword arguments are generated from, so a key declared in C++ appears in both with
// no code of theirs.
#pragma once

#include "params/param_schema.h"

namespace anamorph {

// { "presets": {name: {doc, params: [...]}}, "org": {...}, "dir": {...}, "coin": [...],
//   "camera": [...], "image": [...], "render": [...], "tables": {key: {doc, array, selector,
//   common: [...], variants: {name: {doc, params}}}} (every table of the scene format) };
// unbounded ranges are null.
Json declarations_json();

}  // namespace anamorph
