#pragma once
// RGB → spectral reflectance up-sampling (Smits 1999, "An RGB-to-Spectrum Conversion for
// Reflectances", J. Graphics Tools 4(4)). For colours that come from artists' files (TREE-MAKER
// templates, docs/treemaker.md) rather than measured spectra.
//
// The input is linear Rec.709 (D65) in [0, 1]; components outside are clamped. The result is a
// smooth reflectance in [0, 1] at every wavelength: a sum of Smits's seven basis spectra (white,
// cyan, magenta, yellow, red, green, blue; ten equal bins over 380–720 nm, sampled at the bin
// centres and interpolated linearly) with non-negative weights, clamped to 1 where the bases'
// slight overshoots (1.0149) would exceed it. Outside 380–720 nm the end values are held, so the
// spectrum says nothing physical about the near infrared.

#include "core/math.h"
#include "core/spectrum.h"

namespace sylva {

DenseSpectrum rgb_to_reflectance(const Vec3& linear_rec709);

}  // namespace sylva
