// A shared library that is no plugin: it exports a function, but not
// hapticbench_plugin().
extern "C" __attribute__((visibility("default"))) int not_a_renderer() { return 1; }
