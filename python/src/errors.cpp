// C++ errors as Python exceptions: a bad scene or keyword is anamorph.SceneError (a ValueError)
// carrying the dotted key, the file, line and column; an unreadable file is a ValueError too;
// failing to write is an OSError. Messages have the user's text escaped (math/user_text.h), as the
// CLI prints them: a traceback is printed to a terminal too. The attributes are kept as given.
#include "bindings.h"
#include "camera/stmap.h"
#include "io/image_io.h"
#include "math/user_text.h"
#include "scene/loaders.h"
#include "scene/toml_reader.h"

namespace anamorph::py {

namespace {

// A source that is not a file (keywords, `set=` overrides) has no useful position: the message is
// "key: what", as the scene reader would put it after the position.
bool is_generated(const SourceLoc& loc) { return loc.file.empty() || loc.file[0] == '<'; }

void raise_scene_error(const pb::object& type, const std::string& text, const std::string& key,
                       const SourceLoc& loc, const std::string& message) {
  pb::object e = type(printable(text));
  e.attr("key") = key;
  e.attr("message") = message;
  e.attr("file") = is_generated(loc) ? pb::none() : pb::cast(loc.file);
  e.attr("line") = loc.line;
  e.attr("column") = loc.column;
  PyErr_SetObject(type.ptr(), e.ptr());
}

}  // namespace

void raise_memory_error(const std::string& message) {
  PyErr_SetString(PyExc_MemoryError, message.c_str());
  throw pb::error_already_set();
}

void bind_errors(pb::module_& m) {
  static pb::exception<SceneError> scene_error(m, "SceneError", PyExc_ValueError);
  scene_error.doc() =
      "A bad scene, camera keyword or override (a ValueError). Attributes: key (the dotted key, "
      "e.g. 'camera.fov'), message, and file, line, column when it comes from a file.";
  pb::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const SceneError& e) {
      const std::string text = !is_generated(e.loc) ? std::string(e.what())
                               : e.key.empty()      ? e.message
                                                    : e.key + ": " + e.message;
      raise_scene_error(scene_error, text, e.key, e.loc, e.message);
    } catch (const ParamError& e) {
      const std::string text = e.key.empty() ? e.what() : e.key + ": " + e.message();
      raise_scene_error(scene_error, text, e.key, {}, e.message());
    } catch (const LoadError& e) {
      PyErr_SetString(PyExc_ValueError, printable(e.what()).c_str());
    } catch (const ImageReadError& e) {
      PyErr_SetString(PyExc_ValueError, printable(e.what()).c_str());
    } catch (const ImageIoError& e) {
      PyErr_SetString(PyExc_OSError, printable(e.what()).c_str());
    } catch (const NonCentralCamera& e) {
      PyErr_SetString(PyExc_ValueError, printable(e.what()).c_str());
    } catch (const std::invalid_argument& e) {
      PyErr_SetString(PyExc_ValueError, printable(e.what()).c_str());
    }
  });
}

}  // namespace anamorph::py
