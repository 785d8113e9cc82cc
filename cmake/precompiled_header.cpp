// Empty: the unit that builds a shared precompiled header (cmake/hapticbench.cmake).
