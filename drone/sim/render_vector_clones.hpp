#pragma once
// LABO_VECTOR_CLONES marks a renderer hot loop to be compiled twice, for AVX2 (wider vectors, 32-bit
// multiplies and gathers; chosen once at load time on CPUs that have it) and for the x86-64 baseline.
// Both compute the same integers, so images do not depend on the CPU.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define LABO_VECTOR_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define LABO_VECTOR_CLONES
#endif
