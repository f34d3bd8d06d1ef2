#pragma once
// Synthetic noise for experiments and tests: each vertex moves by a random amount along a random
// direction or along its normal. The amount is scaled by the mean edge length, as in the denoising
// literature (e.g. "fandisk-0.3" = Gaussian noise with sigma = 0.3 x mean edge length).
#include <cstdint>
#include <string>

#include "scanmesh/mesh.h"
#include "scanmesh/schema.h"

namespace scanmesh {

enum class NoiseKind {
  gaussian,   ///< displacement ~ N(0, sigma)
  uniform,    ///< displacement ~ U(-sigma sqrt(3), sigma sqrt(3)): same standard deviation as gaussian
  impulsive,  ///< a fraction of the vertices get N(0, sigma); the rest stay
};
enum class NoiseDirection {
  random,  ///< uniformly distributed unit direction per vertex
  normal,  ///< along the area-weighted vertex normal
};

/// Options of the noise stage; also the schema of the `mesh.noise` pipeline stage.
struct NoiseOptions {
  double level = 0.3;
  NoiseKind kind = NoiseKind::gaussian;
  NoiseDirection direction = NoiseDirection::random;
  std::uint64_t seed = 1;
  double impulsive_fraction = 0.1;
  static const Schema<NoiseOptions>& schema() {
    static const Schema<NoiseOptions> s =
        Schema<NoiseOptions>()
            .number("level", &NoiseOptions::level, closed(0, 100), "x mean edge", "Noise standard deviation.")
            .choice("kind", &NoiseOptions::kind,
                    {{"gaussian", NoiseKind::gaussian}, {"uniform", NoiseKind::uniform}, {"impulsive", NoiseKind::impulsive}},
                    "Distribution: gaussian; uniform with the same deviation; impulsive: a fraction of the vertices only.")
            .choice("direction", &NoiseOptions::direction, {{"random", NoiseDirection::random}, {"normal", NoiseDirection::normal}},
                    "Direction of each vertex's move: random, or along its normal.")
            .seed("seed", &NoiseOptions::seed, "Same seed and mesh, same noise, on every machine.")
            .number("impulsive_fraction", &NoiseOptions::impulsive_fraction, open_closed(0, 1), "share of vertices",
                    "Impulsive noise: the share of vertices that move.");
    return s;
  }
};

NoiseKind parse_noise_kind(const std::string& name);
NoiseDirection parse_noise_direction(const std::string& name);

/// Adds noise to the positions in place; returns sigma in mesh units.
/// \throw UsageError for invalid options.
double add_noise(Mesh& mesh, const NoiseOptions& options);

}  // namespace scanmesh
