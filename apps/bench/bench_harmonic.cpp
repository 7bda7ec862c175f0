// Speed and memory of harmonic binding on the paper's Table 1 multicage (two lotus flowers,
// 68 user vertices, 1024x768), against mean value binding of the same multicage.
//
//   bench_harmonic --benchmark_filter='/4$'      # grid step 4 (the 1 s budget)
//   bench_harmonic --benchmark_filter='Harmonic/1$'   # grid step 1, alone: peak RSS is per process
//
// Counters: unknowns and Dirichlet nodes of the Laplace systems, regions, solves, non-zeros of
// the matrices and of their LDL^T factors, the coefficient matrix in MiB, and the process's
// peak resident set size in MiB (getrusage) after the run.
#include <benchmark/benchmark.h>
#include <sys/resource.h>

#include <opencv2/multicage.hpp>

#include "fixtures.hpp"
#include "harmonic.hpp"

namespace {

using namespace cv::multicage;

const Multicage& lotus() {
    static const Multicage cage = multicage_fixtures::lotusMulticage(cv::Size(1024, 768), 68);
    return cage;
}

double peakRssMiB() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return usage.ru_maxrss / 1024.0;  // ru_maxrss is in KiB on Linux
}

void BM_Harmonic(benchmark::State& state) {
    const int step = static_cast<int>(state.range(0));
    HarmonicStats stats;
    Binding b;
    for (auto _ : state) {
        b = bindHarmonic(lotus(), step, &stats);
        benchmark::DoNotOptimize(b.coefficients.data);
    }
    state.counters["nodes"] = b.nodeCount();
    state.counters["unknowns"] = stats.unknowns;
    state.counters["dirichlet"] = stats.dirichletNodes;
    state.counters["regions"] = stats.components;
    state.counters["solves"] = stats.solves;
    state.counters["A_nnz"] = static_cast<double>(stats.matrixNonZeros);
    state.counters["L_nnz"] = static_cast<double>(stats.factorNonZeros);
    state.counters["coeff_MiB"] = b.coefficients.total() * b.coefficients.elemSize() / 1048576.0;
    state.counters["peak_RSS_MiB"] = peakRssMiB();
}

void BM_MeanValue(benchmark::State& state) {
    const int step = static_cast<int>(state.range(0));
    for (auto _ : state) {
        Binding b = bind(lotus(), MEAN_VALUE, step);
        benchmark::DoNotOptimize(b.coefficients.data);
    }
    state.counters["peak_RSS_MiB"] = peakRssMiB();
}

}  // namespace

BENCHMARK(BM_Harmonic)
    ->Arg(4)
    ->Arg(2)
    ->Unit(benchmark::kMillisecond)
    ->Repetitions(5)
    ->ReportAggregatesOnly(true)
    ->UseRealTime();
BENCHMARK(BM_Harmonic)
    ->Arg(1)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1)
    ->Repetitions(3)
    ->ReportAggregatesOnly(true)
    ->UseRealTime();
BENCHMARK(BM_MeanValue)
    ->Arg(4)
    ->Arg(1)
    ->Unit(benchmark::kMillisecond)
    ->Repetitions(5)
    ->ReportAggregatesOnly(true)
    ->UseRealTime();

BENCHMARK_MAIN();
