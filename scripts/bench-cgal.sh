#!/usr/bin/env bash
# CGAL's 3D regular (weighted Delaunay) triangulation, timed on the spheres of a
# packbed bed (weight = r^2). CGAL is a peer measured side by side with packbed,
# never a dependency: nothing in the project builds or links against it.
# Times only the triangulation (CGAL's spatial sort included, file reading
# excluded); prints one line per run:
#   points N cells C finite_cells F seconds S maxrss_mb M vertices V
# Usage: scripts/bench-cgal.sh PARTICLES_CSV [RUNS]   (RUNS defaults to 3)
# Installs Debian's header-only libcgal-dev with apt-get if it is missing.
set -euo pipefail
CSV="${1:?particles.csv of a 3D bed}"
RUNS="${2:-3}"
[[ -r "$CSV" ]] || { echo "cannot read $CSV" >&2; exit 2; }
[[ "$RUNS" =~ ^[1-9][0-9]*$ ]] || { echo "RUNS must be a positive integer, got '$RUNS'" >&2; exit 2; }

if ! dpkg -s libcgal-dev >/dev/null 2>&1; then
    apt-get update
    apt-get install -y libcgal-dev
fi

WORK="$(mktemp -d)"
trap 'rm -rf "$WORK"' EXIT

cat > "$WORK/rt3.cpp" <<'CPPEOF'
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Regular_triangulation_3.h>
#include <sys/resource.h>
#include <chrono>
#include <cstdio>
#include <vector>

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Regular = CGAL::Regular_triangulation_3<Kernel>;
using Weighted = Kernel::Weighted_point_3;

int main(int argc, char** argv) {
    if (argc != 2) { std::fprintf(stderr, "usage: rt3 POINTS (lines: x y z w)\n"); return 2; }
    std::FILE* f = std::fopen(argv[1], "r");
    if (!f) { std::perror(argv[1]); return 2; }
    std::vector<Weighted> input;
    double x, y, z, w;
    while (std::fscanf(f, "%lf %lf %lf %lf", &x, &y, &z, &w) == 4)
        input.emplace_back(Kernel::Point_3(x, y, z), w);
    std::fclose(f);

    const auto start = std::chrono::steady_clock::now();
    Regular rt;
    rt.insert(input.begin(), input.end());  // range insert: spatial sort, then insertion
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    struct rusage usage;
    getrusage(RUSAGE_SELF, &usage);  // ru_maxrss: KiB on Linux
    std::printf("points %zu cells %zu finite_cells %zu seconds %.3f maxrss_mb %.1f vertices %zu\n",
                input.size(), static_cast<std::size_t>(rt.number_of_cells()),
                static_cast<std::size_t>(rt.number_of_finite_cells()), secs,
                usage.ru_maxrss / 1024.0, static_cast<std::size_t>(rt.number_of_vertices()));
    return 0;
}
CPPEOF
g++ -O3 -DNDEBUG -std=c++17 "$WORK/rt3.cpp" -o "$WORK/rt3" -lgmp -lmpfr

# Columns by header name, so a change in column order does not matter.
awk -F, -v out="$WORK/points.txt" '
    NR == 1 {
        sub(/\r$/, "")
        for (i = 1; i <= NF; i++) col[$i] = i
        if (!("x" in col) || !("y" in col) || !("r" in col)) {
            print "no x, y or r column in the header: " $0 > "/dev/stderr"; exit 3
        }
        if (!("z" in col)) {
            print "2D bed (no z column): only 3D beds are handled" > "/dev/stderr"; exit 4
        }
        next
    }
    { sub(/\r$/, ""); r = $col["r"]; printf "%s %s %s %.17g\n", $col["x"], $col["y"], $col["z"], r * r > out }
' "$CSV"
[[ -s "$WORK/points.txt" ]] || { echo "no particles in $CSV" >&2; exit 2; }

for _ in $(seq "$RUNS"); do
    "$WORK/rt3" "$WORK/points.txt"
done
