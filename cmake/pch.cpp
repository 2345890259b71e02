// The translation unit that builds the shared precompiled headers (CMakeLists.txt, CTB_PCH).
