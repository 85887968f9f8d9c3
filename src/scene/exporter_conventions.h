// scene/exporter_conventions.h — what a particular exporter means by the legacy material numbers it writes.
// Blender's exporters turn its Principled BSDF (base colour, metallic, specular, roughness) into Phong-era
// numbers their own way: its OBJ exporter writes Ks = Specular and Ns = (1 - Roughness)^2 x 1000; its
// FBX exporter SpecularColor = the base colour, SpecularFactor = Specular / 2, ShininessExponent =
// ((1 - Roughness) x 10)^2 and ReflectionFactor = Metallic (read from Blender 3.4's exporters and the
// files they wrote, tests/data/blender). Read generically, its glossy materials come out several times too
// shiny. The loaders recognise a file Blender wrote by its own stamp and invert its conversion instead.
// Its FBX and Collada exporters also write the camera's angle along the longer side of the picture (its
// default sensor fit, AUTO) as the horizontal one: for a portrait picture that is the vertical angle.
#pragma once

#include "materials/phong.h"

#include <string>

namespace symphong {

/// Whether Blender wrote this FBX file: its header (binary or ASCII) names Blender as its creator.
bool fbxWrittenByBlender(const std::string& path);
/// Whether Blender wrote this Collada file: its <authoring_tool> (near the start) names Blender.
bool colladaWrittenByBlender(const std::string& path);
/// Whether Blender wrote this MTL text: its first line is Blender's comment ("# Blender 3.4.1 MTL File: ...").
bool mtlWrittenByBlender(const std::string& text);

/// Blender's Principled parameters as a Phong material: F0 = 0.08 x specular (Blender's specular scale,
/// 0.5 giving glTF's 0.04), then the glTF mapping of materials/phong.h (rho_s = F0 (1 - m) + b m,
/// rho_d = b (1 - m) (1 - F0), n from alpha = roughness^2).
void blenderPrincipledToPhong(const Color& base, double metallic, double specular, double roughness, Color& rhoD, Color& rhoS,
                              double& exponent);

}  // namespace symphong
