// jetrace-bench track-load and density (docs/TRACKS.md, "Figures"):
//   track-load  the landscape at one density (or --track) as OBJ and as .jtrack:
//               load time of each through load_track(), their ratio, the
//               grid build, and the bytes per triangle of the loaded track
//               and its scene (counted from the arrays, and as resident
//               memory grown);
//   density     the landscape at 32 k, 130 k, 520 k and 2 M triangles: ns
//               per car-step of 8 AI cars, triangles gathered per car-step,
//               and the cost relative to the coarsest; --track adds
//               tracks, --cell-m compares cell edges in the same run.
#pragma once

#include <string>
#include <vector>

namespace jetrace::bench {

struct TrackLoadOptions {
    /// Squares per side of the landscape (2 n^2 triangles; 1024: 2,097,152).
    int squares = 1024;
    /// Timed loads of the .jtrack file; the median is reported (unit: loads).
    int repeats = 5;
    /// Timed loads of the OBJ file or --track (unit: loads).
    int obj_repeats = 1;
    /// A track to load instead of the landscape (a path load_track reads:
    /// OBJ, manifest); "" = the landscape, written as OBJ.
    std::string track;
    /// Where the two files are written ("" = the temporary directory).
    std::string dir;
};

int run_track_load(const TrackLoadOptions& o);

struct DensityOptions {
    /// Squares per side of each mesh (2 n^2 triangles each).
    std::vector<int> squares = {128, 256, 512, 1024};
    /// Simulated seconds of each timed race (unit: s).
    double seconds = 10;
    /// Timed races per density; the median is reported.
    int repeats = 3;
    /// Tracks timed after the landscapes (names or paths load_track reads).
    std::vector<std::string> tracks;
    /// Cell edges of the collision grid, each timed side by side in every
    /// round (unit: m; 0 = the grid's own rule).
    std::vector<double> cell_sizes_m = {0.0};
};

int run_density(const DensityOptions& o);

}  // namespace jetrace::bench
