// The anchor of the precompiled header (CMakeLists.txt, FLIPFLUX_PCH): nothing of its own.
