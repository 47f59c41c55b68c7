// Every built-in output sink kind, one line each: ANAMORPH_SINK(its SinkKind, the file that
// defines it). The registry (io/image_sink.cpp) declares and lists the kinds from here, in this
// order (the first is the format of a name without an extension written directly, such as
// /dev/stdout), and the build (io/sources.cmake) compiles the files named here: a new output is
// its file and its line. (No include guard: read once per use, with ANAMORPH_SINK defined.)
ANAMORPH_SINK(kPngSink, sink_png.cpp)
ANAMORPH_SINK(kExrSink, sink_exr.cpp)
ANAMORPH_SINK(kFloSink, sink_flo.cpp)
