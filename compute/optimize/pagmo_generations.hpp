// pagmo2's CMA-ES and xNES behind a table of functions: the interface between FIRD and
// libfird_pagmo.so, the module that alone links libpagmo. The program loads the module
// (io/program_files.hpp) the first time a population search runs, so every other command
// starts without loading pagmo: its static initialization alone took 60-70 ms of each
// process's start on the AMD EPYC of docs/benchmarks.md ("Start-up: pagmo loaded only by a
// population search"). Only standard types cross: the module is built with the program, in
// the same build, and the program checks the table's stamp against its own (the engine
// headers' SHA-256: io/program_files.hpp's program_module_table).
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

namespace fird {

// The file the module is built as, and the symbol that returns its table.
inline constexpr const char* kPagmoModuleFile = "libfird_pagmo.so";
inline constexpr const char* kPagmoModuleSymbol = "fird_pagmo_generations";

// What a population run is: the algorithm, its first spread and generator seed, and the box
// of the sample coordinates it searches (pagmo's problem bounds).
struct PagmoRunSpec {
    bool xnes = false; // else CMA-ES
    double sigma0 = 0.0;
    std::uint32_t seed = 0;
    std::vector<double> lo, hi;
};

// A fitness call: the value pagmo asks of a point in the sample coordinates.
using PagmoFitness = std::function<double(const std::vector<double>& c)>;

// The module's functions. A run is an opaque handle owned by the caller (destroy it).
// Each evolves one generation (pagmo's evolve with gen = 1 and memory kept between calls);
// evolve_copy does so on copies of the algorithm and the population, leaving the run as it
// was (FIRD's first pass over a generation, which only notes the points asked for).
// Exceptions (pagmo's, or the fitness callback's own) propagate to the caller.
struct PagmoGenerations {
    const char* stamp = nullptr; // FIRD_MODULE_STAMP of the module's build: first, always
    void* (*create)(const PagmoRunSpec& spec, PagmoFitness fitness) = nullptr;
    // Adds an individual with its known fitness (the first generation's members).
    void (*push_back)(void* run, const std::vector<double>& c, double fitness) = nullptr;
    void (*evolve_copy)(void* run) = nullptr;
    void (*evolve)(void* run) = nullptr;
    void (*destroy)(void* run) = nullptr;
};

} // namespace fird
