#!/usr/bin/python3
"""Plants known bugs in a copy of the source, one at a time, and runs the test suite after each.
(Debian's Python, as CI has it: under a pyenv `python3` the shims put that Python first on the PATH of
every test, and Blender, which blender.addon starts, then imports from it and finds no numpy.)

Usage: /usr/bin/python3 scripts/planted-bugs.py [--only NAME,...] [--jobs N] [--check] [--reuse] [--first]
       (--only: these bugs, in this order)

For every bug below it applies one exact text replacement to a git worktree of HEAD (beside the
checkout, as ../<checkout>-planted, so that scenes referring to ../shared resolve), builds it under
build/planted/, runs `ctest`, records which tests failed, and reverts the file. The table it
prints is the one in docs/testing.md ("Planted bugs"). A bug whose text is no longer in the source is
reported as STALE (the code moved; update the replacement), never silently skipped. A bug that no test
catches is reported as MISSED and makes the script exit 1; so is one that only the golden images (tests/golden) or
python.test_docs catch, since those fail for any change of output, right or wrong. `--check` only checks
that every planted text is still in the source, once. `--first` answers only whether a bug is caught: with a
bug planted, ctest runs without the golden/docs tests and stops at the first failure (`--stop-on-failure`), so
a row names the first test that failed (or two, with --jobs 2) rather than all of them; the tests that caught
the bug last time (FIRST_TRIED) run first, and the whole suite only when none of them fails. The clean tree
still runs the whole suite. A pass over all bugs takes an hour or two this way, not a day.
"""
import argparse
import os
import re
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
WORK = os.path.join(ROOT, "build", "planted")
TREE = ROOT.rstrip("/") + "-planted"
BUILD = os.path.join(WORK, "build")

# name, what it simulates, file, exact old text, new text; or name, what, file, [(old, new), ...]
BUGS = [
    ("pdf-2pct", "cosine pdf 2% too high (sampling unchanged)", "src/sampling/warp.h",
     "return w.z > 0 ? w.z * kInvPi : 0.0;", "return w.z > 0 ? 1.02 * w.z * kInvPi : 0.0;"),
    ("below-horizon", "1% of cosine directions mirrored below the horizon", "src/sampling/warp.h",
     "    return {d.u, d.v, z};\n}\ninline double cosineHemispherePdf",
     "    return {d.u, d.v, p.u < 0.01 ? -z : z};\n}\ninline double cosineHemispherePdf"),
    ("brdf-normalisation", "Phong lobe normalised by (n+1)/(2 pi) instead of (n+2)/(2 pi)", "src/materials/phong.cpp",
     "if (ca > 0) f += m.rhoS * ((m.exponent + 2.0) / kTwoPi", "if (ca > 0) f += m.rhoS * ((m.exponent + 1.0) / kTwoPi"),
    ("nee-no-cosine", "light sampling forgets the cosine at the shading point", "src/render/path_tracer.cpp",
     "(wiLocal.z * w / s.pdf)", "(w / s.pdf)"),
    ("mis-swapped", "light sampling's MIS weight takes the estimator's density as its own", "src/render/path_tracer.cpp",
     "powerHeuristic(s.pdf, estimator_.misPdf(sc, wiLocal) * misScale)", "powerHeuristic(estimator_.misPdf(sc, wiLocal) * misScale, s.pdf)"),
    ("roulette-unweighted", "Russian roulette survivors not divided by the survival probability", "src/render/path_tracer.cpp",
     "if (!branching) return weight * radiance(origin, wi, depth + 1, nextPath, s.misPdf, next, pc) / survive;",
     "if (!branching) return weight * radiance(origin, wi, depth + 1, nextPath, s.misPdf, next, pc);"),
    ("thread-rng", "cosine estimator draws from a per-thread generator instead of the sampler", "src/estimators/basic.cpp",
     "    const Vec3 wi = sampleCosineHemisphere(samples.get2D());\n    pushWeighted(ctx, wi, cosineHemispherePdf(wi), out);",
     "    static thread_local Rng rng(7, 7);\n    (void)samples;\n    const Vec3 wi = sampleCosineHemisphere(rng.uniform2());\n"
     "    pushWeighted(ctx, wi, cosineHemispherePdf(wi), out);"),
    ("non-atomic-write", "images written straight onto the target instead of a temporary file", "src/io/files.cpp",
     "        write(tmp);\n        std::filesystem::rename(tmp, path);", "        write(path);"),
    ("two-sided-emitter", "emitters emit from their back side too", "src/render/path_tracer.cpp",
     "    if (mat.isEmissive() && frontFace)\n", "    if (mat.isEmissive())\n"),
    ("half-pixel-shift", "camera rays shifted by half a pixel", "src/render/renderer.cpp",
     "x + jitter.u, y + jitter.v, o, d);", "x + 0.5 + jitter.u, y + jitter.v, o, d);"),
    ("exposure-ignored", "the PNG writer ignores --exposure", "src/io/image.cpp",
     "bytes[3 * i + c] = toSrgb8(img.pixels[i][c], exposure);", "bytes[3 * i + c] = toSrgb8(img.pixels[i][c], 1.0);"),
    ("exr-half-ignored", "--exr-half writes float channels", "src/io/image.cpp",
     "const Imf::PixelType type = half ? Imf::HALF : Imf::FLOAT;", "const Imf::PixelType type = Imf::FLOAT;\n        (void)half;"),
    ("max-depth-ignored", "the command line drops --max-depth", "src/render/settings.cpp",
     "    settings.trace.maxDepth = o.maxDepth;\n", "\n"),
    ("sobol-not-per-pixel", "the Sobol' 2D scramble ignores the pixel and seed (every pixel the same points)",
     "src/sampling/sampler.h",
     "    static Point2 pairValue(std::uint64_t key, std::uint32_t index, std::uint32_t count, std::uint64_t dim) {\n        const std::uint64_t h = mixSeed(key, 2 * dim);",
     "    static Point2 pairValue(std::uint64_t key, std::uint32_t index, std::uint32_t count, std::uint64_t dim) {\n        const std::uint64_t h = mixSeed(0 * key, 2 * dim);"),
    ("cutout-shadow-rays", "a cut-out that camera rays see but shadow rays ignore", "src/accel/accel.cpp",
     "        rtcSetGeometryOccludedFilterFunction(geom, cutOutFilter);\n", "\n"),
    ("nested-node-transform", "a file whose nodes nest: the parent's transform dropped", "src/scene/assimp_loader.cpp",
     "world * node->mChildren[i]->mTransformation", "node->mChildren[i]->mTransformation"),
    ("env-rotation-reversed", "the environment map turned the other way (consistently, in both directions of the mapping)",
     "src/scene/environment_map.cpp",
     [("u = 0.5 + phi / kTwoPi - rotation_ / 360.0;", "u = 0.5 + phi / kTwoPi + rotation_ / 360.0;"),
      ("kTwoPi * (u - 0.5 + rotation_ / 360.0)", "kTwoPi * (u - 0.5 - rotation_ / 360.0)")]),
    ("env-density-no-sine", "the environment map's sampling table forgets sin(theta) (still unbiased, wrong density)",
     "src/scene/environment_map.cpp",
     [("        const double sinTheta = std::sin(kPi * (y + 0.5) / h);\n", ""), ("= y0 * sinTheta;", "= y0;")]),
    ("texture-gamma-2.2", "textures decoded with gamma 2.2 instead of the sRGB curve's 2.4 segment", "src/texture/texture.cpp",
     "std::pow((e + 0.055) / 1.055, 2.4)", "std::pow((e + 0.055) / 1.055, 2.2)"),
    ("texture-negative-truncated", "texture coordinates rounded toward zero (wrong texels left of and below the origin)",
     "src/texture/texture.cpp", "const double fx = std::floor(x), fy = std::floor(y);",
     "const double fx = std::trunc(x), fy = std::trunc(y);"),
    ("spot-linear-falloff", "the spot light falls off linearly between its cones instead of by smoothstep", "src/scene/light.h",
     "return t * t * (3.0 - 2.0 * t);", "return t;"),
    ("mpi-unpack-swapped", "rank 0 takes the other ranks' sums of squares for their sums and the other way round",
     "src/distrib/render.cpp", "s.sum[p] = Color(in[k], in[k + 1], in[k + 2]), s.sumSq[p] = Color(in[k + 3], in[k + 4], in[k + 5]);",
     "s.sumSq[p] = Color(in[k], in[k + 1], in[k + 2]), s.sum[p] = Color(in[k + 3], in[k + 4], in[k + 5]);"),
    # Not a bug to plant: a rank that ignores the state sent with its grant renders the tile from its own
    # leftovers (sample 0, or an earlier correct prefix of the same sums), which gives the same sums with
    # more work; no test of output can tell (tried 2026-12-02: only a flaky test failed).
    ("resume-ignores-seed", "a checkpoint is resumed whatever seed the command line gives",
     "src/render/settings.cpp", 's.push_back(F("seed", "--seed", "random seed", member(&RenderOptions::seed)));',
     's.push_back(F("seed", "--seed", "random seed", member(&RenderOptions::seed)).keepsPixels());'),
    ("passes-restart-sums", "each pass starts its pixels' sums from zero instead of the state's",
     "src/render/renderer.cpp", "Color sum = state.sum[pixel], sumSq = state.sumSq[pixel];", "Color sum(0.0), sumSq(0.0);"),
    ("python-array-bgr", "the module's image arrays come out in BGR order", "src/python/arrays.cpp",
     "for (int c = 0; c < 3; ++c) out[3 * i + c] =", "for (int c = 0; c < 3; ++c) out[3 * i + 2 - c] ="),
    ("memory-boundary", "an allocation of exactly the memory budget refused", "src/io/memory.cpp",
     "if (bytes <= budget) return;", "if (bytes < budget) return;"),
    ("sobol-pair-shared-scramble", "a Sobol' pair's y coordinate scrambled with its x coordinate's seed", "src/sampling/sampler.h",
     "fixedToUnit(owenScrambledSobol1(j, static_cast<std::uint32_t>(h >> 32)))};", "fixedToUnit(owenScrambledSobol1(j, static_cast<std::uint32_t>(h)))};"),
    # Issue 35 item 3: the code written or moved since the pass of 2026-12-02.
    ("mix-orbit-unweighted", "symmetric-mix's branch mode weights each of an orbit's R copies f cos / q instead of f cos / (R q)",
     "src/estimators/symmetric_mix.cpp", "for (int j = 0; j < orbit_; ++j) push(ctx, copies(j), static_cast<double>(orbit_), out);",
     "for (int j = 0; j < orbit_; ++j) push(ctx, copies(j), 1.0, out);"),
    ("mix-family-not-offset", "symmetric-mix's copies of an orbit all take the first copy's family (no j / R offset of t)",
     "src/estimators/symmetric_mix.cpp", "double t = o_.t + static_cast<double>(j) / orbit_;", "double t = o_.t;"),
    ("ckpt-ears-ratios-swapped", "a checkpoint's learned EARS ratios read back in the other order (variance for moment)",
     "src/render/checkpoint.cpp",
     "l.factors.varianceRatio[e.factorCells[i]] = e.factorRatios[3 * i];\n        l.factors.momentRatio[e.factorCells[i]] = e.factorRatios[3 * i + 1];",
     "l.factors.varianceRatio[e.factorCells[i]] = e.factorRatios[3 * i + 1];\n        l.factors.momentRatio[e.factorCells[i]] = e.factorRatios[3 * i];"),
    ("region-error-per-pixel", "the standard error of a region's mean divided by sqrt(pixels) instead of pixels",
     "src/render/render_state.cpp", "return {meanSum / c, std::sqrt(varSum) / c};", "return {meanSum / c, std::sqrt(varSum / c)};"),
    ("target-error-best-region", "--target-error stops when the best --target-region meets it instead of the worst",
     "src/render/progressive.cpp", "for (const PixelRect& r : regions) worst = std::max(worst, state.regionError(r).relative());",
     "for (const PixelRect& r : regions) worst = std::min(worst, state.regionError(r).relative());"),
    ("time-limit-ignores-pass", "the pass size ignores the time left under --time (the last pass overshoots it)",
     "src/render/progressive.cpp",
     "    if (rules.timeLimit > 0 && secondsPerSpp > 0) n = std::min(n, std::floor((rules.timeLimit - state.seconds) / secondsPerSpp));\n",
     "\n"),
    ("relmse-epsilon", "relMSE divides by (Y_ref + 0.01)^2 instead of Y_ref^2 + 0.01", "src/compare/metrics.cpp",
     "rel += d2 / (yr * yr + 0.01);", "rel += d2 / ((yr + 0.01) * (yr + 0.01));"),
    ("hdrflip-exposure-step", "HDR-FLIP's exposures step (stop - start) / count instead of / (count - 1) (the last one short of stop)",
     "src/compare/flip.cpp", "const double step = count > 1 ? (stop - start) / (count - 1) : 0.0;",
     "const double step = count > 1 ? (stop - start) / count : 0.0;"),
    ("ply-strip-parity", "a PLY strip's winding alternates by the index's position in the list, not in its strip (after a -1 restart)",
     "src/scene/ply_loader.cpp", "if ((k - start) % 2 == 0) add(idx[k - 2], idx[k - 1], idx[k]);",
     "if (k % 2 == 0) add(idx[k - 2], idx[k - 1], idx[k]);"),
    ("normal-map-no-handedness", "a normal map's bitangent ignores the tangent's sign (mirrored UVs bend the wrong way)",
     "src/scene/shading_normal.cpp", "const Vec3 b = cross(n, t) * sign;", "const Vec3 b = cross(n, t);"),
    ("normal-map-strength-on-z", "a normal map's strength scales z as well as x and y (so it does nothing)",
     "src/scene/shading_normal.cpp", "(2 * c.y - 1) * tx.normalScale, 2 * c.z - 1);",
     "(2 * c.y - 1) * tx.normalScale, (2 * c.z - 1) * tx.normalScale);"),
    ("height-slope-doubled", "a height map's slope along u divided by one step instead of two (twice as steep)",
     "src/scene/shading_normal.cpp", "const double dhdu = (height(uv.u + du, uv.v) - height(uv.u - du, uv.v)) / (2 * du);",
     "const double dhdu = (height(uv.u + du, uv.v) - height(uv.u - du, uv.v)) / du;"),
    ("bump-shadowing-terms", "the shadow-terminator term -g^3 + g^2 + g written -g^2 + g^3 + g", "src/scene/shading_normal.cpp",
     "return -g2 * g + g2 + g;", "return -g2 + g2 * g + g;"),
    ("texture-transform-rotation", "KHR_texture_transform's rotation turned the other way", "src/scene/assimp_materials.cpp",
     "m01 = -sy * std::sin(r), m10 = sx * std::sin(r),", "m01 = sy * std::sin(r), m10 = -sx * std::sin(r),"),
    ("texture-transform-offset-v", "KHR_texture_transform's offset along t not flipped to symphong's v", "src/scene/assimp_materials.cpp",
     "1 - m11 - oy};", "1 - m11 + oy};"),
    ("range-lower-exclusive", "a setting's range excludes its lower bound (--spp 1, --time 0 refused)", "src/util/schema.h",
     "if (f.hasRange() && !(v >= f.lo && v <= f.hi))", "if (f.hasRange() && !(v > f.lo && v <= f.hi))"),
    ("split-range-zero", "--split 0 accepted (renders as --split 1)", "src/render/settings.cpp",
     "member(&RenderOptions::split))\n                        .range(1, 64));", "member(&RenderOptions::split))\n                        .range(0, 64));"),
    ("answer-factor-mse", "the answer's relMSE line quotes its factors by MSE", "src/study/answer.cpp",
     "const ErrorMeasure m = rel ? ErrorMeasure::RelMse : ErrorMeasure::Mse;", "const ErrorMeasure m = ErrorMeasure::Mse;"),
    ("fbx-blender-specular-half", "Blender's FBX SpecularFactor (Specular / 2) taken as Specular: every glossy material's rho_s halved",
     "src/scene/assimp_materials.cpp", "blenderPrincipledToPhong(out.rhoD, metallic, 2.0 * factor, roughness,",
     "blenderPrincipledToPhong(out.rhoD, metallic, factor, roughness,"),
    ("fbx-blender-roughness", "Blender's FBX ShininessExponent ((1 - R) 10)^2 undone with / 100 instead of / 10 (R near 1: rough)",
     "src/scene/assimp_materials.cpp", "std::sqrt(std::max(0.0, static_cast<double>(shininess))) / 10.0;",
     "std::sqrt(std::max(0.0, static_cast<double>(shininess))) / 100.0;"),
    ("obj-blender-roughness", "Blender's MTL Ns = (1 - R)^2 1000 undone without the square root", "src/scene/obj_loader.cpp",
     "1.0 - std::sqrt(std::clamp(mt.shininess / 1000.0, 0.0, 1.0));", "1.0 - std::clamp(mt.shininess / 1000.0, 0.0, 1.0);"),
    ("ears-continuation-unweighted", "EARS's continuations not averaged (their sum, not divided by their number n)", "src/render/path_tracer.cpp",
     "        L += value / divisor;\n", "        L += value;\n"),
    ("ears-epoch-not-cut", "an EARS render not cut at the epochs' ends (a pass spans epochs: factors from the wrong epoch)",
     "src/render/renderer.cpp", "renderSegment(scene, accel, estimator, settings, state, std::min(upTo, ears::epochEnd(reached)), progress);",
     "renderSegment(scene, accel, estimator, settings, state, upTo, progress);"),
]

# --first: the tests that caught each bug last time (docs/testing.md), run before the rest of the suite.
# A guess only: when none of them fails, the whole suite runs.
FIRST_TRIED = {
    'answer-factor-mse': ['StudyAnswer.MostEfficientLinesQuoteTheRatiosOfTheirOwnMeasure', 'TinyStudy.AnswerFactorsAreTheRatiosOfResultsCsv'],
    'fbx-blender-specular-half': ['Assimp.BlenderGlossyMaterialsAreTheirPrincipledParameters', 'Assimp.Blender'],
    'fbx-blender-roughness': ['Assimp.BlenderGlossyMaterialsAreTheirPrincipledParameters', 'Assimp.Blender'],
    'obj-blender-roughness': ['Assimp.BlenderGlossyMaterialsAreTheirPrincipledParameters', 'Assimp.Blender'],
    'target-error-best-region': ['Progressive.TargetErrorWaitsForItsWorstRegion'],
    'time-limit-ignores-pass': ['Progressive.TimeLimitSizesThePassesToTheTimeLeft'],
    'region-error-per-pixel': ['Progressive.ErrorEstimateOfTheMeanMatchesItsSpreadOverSeeds', 'Progressive.TargetErrorStopsWithinTheStatedError'],
    'ckpt-ears-ratios-swapped': ['EarsCheckpoint.ResumesInsideAnEpochBitForBit', 'EarsRender.SameImage', 'EarsRender.TheClosedFurnace'],
    'ears-continuation-unweighted': ['EarsRender.MeanImageAgreesWithPhongOnEveryStudyScene', 'EarsRender.MeanImage', 'EarsRender.TheClosedFurnaceKeepsItsClosedForm'],
    'ears-epoch-not-cut': ['EarsRender.SameImageAtAnyThreadCountAndAnyPasses', 'EarsCheckpoint.ResumesInsideAnEpochBitForBit', 'EarsRender.SameImage'],
    'mix-orbit-unweighted': ['SymmetricMixDiffuse.ConstantRadianceGivesZeroVarianceLikeCosine'],
    'mix-family-not-offset': ['SymmetricMixDensity.AnOrbitSplitsBetweenTheFamiliesInProportion', 'SymmetricMixDensity.AnOrbit'],
    'relmse-epsilon': ['StudyMetrics.ErrorsOfAKnownPerturbation'],
    'hdrflip-exposure-step': ['HdrFlip.AgreesWithNvidiaReferenceTool'],
    'ply-strip-parity': ['Ply.TriangleStripsLoadInFullWithTheirWinding'],
    'normal-map-no-handedness': ['NormalMaps.ConstantMapTiltsTheLambertCosineInItsTangentFrame', 'NormalMaps.PerturbedNormalIsTheMapsVectorInTheTangentFrame'],
    'normal-map-strength-on-z': ['NormalMaps.ConstantMapTiltsTheLambertCosineInItsTangentFrame'],
    'height-slope-doubled': ['NormalMaps.HeightRampTiltsTheNormalAgainstItsSlope'],
    'bump-shadowing-terms': ['NormalMaps.BumpShadowingTermFollowsItsFormula'],
    'texture-transform-rotation': ['NormalMaps.KhrTextureTransformFollowsTheExtensionsFormula'],
    'texture-transform-offset-v': ['NormalMaps.KhrTextureTransformFollowsTheExtensionsFormula'],
    'range-lower-exclusive': ['Schema.JsonRoundTripAndErrorsNameTheKey', 'Schema.AStudysSettingsInResultsJsonGiveItsConfigurationBack', 'CliOptions.OutputHas'],
    'split-range-zero': ['python.test_errors'],
    'mis-swapped': ['Furnace.ClosedSphereGivesLeOverOneMinusAlbedo', 'CornellAgreement.WithoutLightSamplingTheImageIsTheSame', 'CornellAgreement.WithoutLightSampling'],
    'roulette-unweighted': ['Furnace.ClosedSphereGivesLeOverOneMinusAlbedo', 'CornellAgreement.WithoutLightSamplingTheImageIsTheSame', 'CornellAgreement.WithoutLightSampling'],
    'pdf-2pct': ['Warps.PdfsIntegrateToOne', 'Warps.CosineHemisphereFitsItsPdf', 'EstimatorDirections.PhongMixtureFitsItsPdf'],
    'below-horizon': ['Warps.CosineHemisphereFitsItsPdf', 'EstimatorDirections.PhongMixtureFitsItsPdf', 'EstimatorDensities.OneDirectionFollowsTheReportedMisPdf'],
    'brdf-normalisation': ['Phong.DirectionalAlbedoIsAtMostOneAndMatchesMonteCarlo', 'EveryEstimatorAndSampler/EstimatorFurnace.MatchesTheDirectionalAlbedo/uniform_independent', 'EveryEstimatorAndSampler/EstimatorFurnace.MatchesTheDirectionalAlbedo/uniform_stratified'],
    'nee-no-cosine': ['Furnace.ClosedSphereGivesLeOverOneMinusAlbedo', 'CornellAgreement.WithoutLightSamplingTheImageIsTheSame', 'LambertFormula.DirectLightOnAPlaneMatchesRegionByRegion'],
    'thread-rng': ['Determinism.SameSeedSameImageAtAnyThreadCountForEverySampler', 'TinyStudy.TheReferenceIsCachedAndReusedOnlyWhenTheSettingsMatch'],
    'non-atomic-write': ['AtomicWrite.AFailedImageWriteLeavesTheTargetUntouched'],
    'two-sided-emitter': ['Emitters.EmitFromTheirFrontSideOnly'],
    'half-pixel-shift': ['Camera.ImageEdgesLandOnPixelEdges', 'LambertFormula.DirectLightOnAPlaneMatchesRegionByRegion', 'Lights.PointLightAboveAPlaneGivesRhoOverPiICosOverDSquared'],
    'exposure-ignored': ['CliOptions.ExposureScalesThePngAndNotTheExr'],
    'exr-half-ignored': ['Exr.FloatRoundTripIsExactAndHalfIsClose', 'CliOptions.ExrHalfWritesHalfChannelsAndFloatByDefault', 'python.test_render'],
    'max-depth-ignored': ['CliOptions.MaxDepthLimitsTheBounces'],
    'sobol-not-per-pixel': ['EveryEstimatorAndSampler/EstimatorFurnace.MatchesTheDirectionalAlbedo/uniform_sobol', 'EveryEstimatorAndSampler/EstimatorFurnace.MatchesTheDirectionalAlbedo/cosine_sobol', 'EveryEstimatorAndSampler/EstimatorFurnace.MatchesTheDirectionalAlbedo/phong_sobol'],
    'cutout-shadow-rays': ['CutOutShadows.APerforatedScreenCastsTheShadowOfItsSolidParts'],
    'nested-node-transform': ['NodeTransforms.GltfChildNodesAreTransformedByTheirParents', 'NodeTransforms.ColladaChildNodesAreTransformedByTheirParents'],
    'env-rotation-reversed': ['EnvironmentMap.RotatedMapIsSeenAndSampledWhereTheFormulaPutsItsTexels'],
    'env-density-no-sine': ['EnvironmentMap.RotatedMapIsSeenAndSampledWhereTheFormulaPutsItsTexels'],
    'texture-gamma-2.2': ['TexturedRender.MapKdCheckerboardRendersItsLinearMean', 'TextureLookup.SrgbCurveIsTheStandardsFormula'],
    'texture-negative-truncated': ['Render.NoPixelIsNaNOnAnyBundledScene', 'Texture.BilinearLookupBetweenTexelCentres', 'TextureLookup.BilinearWithEveryWrapModeMatchesAnExplicitPlaneOfTiles'],
    'spot-linear-falloff': ['Emitters.SpotLightFallsOffAsItsSmoothstepBetweenTheCones'],
    'python-array-bgr': ['python.test_array_layout', 'python.test_render'],
    'memory-boundary': ['Memory.ExactlyTheBudgetPassesAndOneByteMoreIsRefused'],
    'sobol-pair-shared-scramble': ['EveryEstimatorAndSampler/EstimatorFurnace.MatchesTheDirectionalAlbedo/uniform_sobol', 'EveryEstimatorAndSampler/EstimatorFurnace.MatchesTheDirectionalAlbedo/cosine_sobol', 'EveryEstimatorAndSampler/EstimatorFurnace.MatchesTheDirectionalAlbedo/phong_sobol'],
    'mpi-unpack-swapped': ['mpi.render.identical.independent.np2', 'mpi.render.identical.independent.np3', 'mpi.render.identical.sobol.np2'],
    'resume-ignores-seed': ['python.test_long_render', 'checkpoint.refused'],
    'passes-restart-sums': ['Progressive.PassesInAnyOrderGiveTheOnePassImageBitForBit', 'Progressive.TargetErrorStopsWithinTheStatedError', 'Checkpoint.ReadsBackExactlyAndResumesToTheOnePassImage'],
}

# Tests that fail for any change of output, right or wrong: a bug they alone catch counts as missed.
NOT_INDEPENDENT = re.compile(r"^(Renders/Golden\.|Golden|python\.test_docs$)")


def replacements(old, new):
    """A bug is one (old, new) replacement or, with new None, a list of them (all applied)."""
    return old if new is None else [(old, new)]


def plant(text, pairs):
    """The text with every replacement applied, or None when one's old text is not there exactly once."""
    for old, new in pairs:
        if text.count(old) != 1:
            return None
        text = text.replace(old, new)
    return text


def check_only(only):
    """--check: every bug's text is in the working tree's source exactly once (no build, no tests)."""
    stale = 0
    for bug in BUGS:
        name, rel, pairs = bug[0], bug[2], replacements(*bug[3:5]) if len(bug) == 5 else bug[3]
        if only and name not in only:
            continue
        with open(os.path.join(ROOT, rel)) as f:
            ok = plant(f.read(), pairs) is not None
        stale += not ok
        print(f"{name}: {'ok' if ok else 'STALE'}")
    return 1 if stale else 0


def run(cmd, cwd, timeout=None):
    return subprocess.run(cmd, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=timeout)


def prepare():
    os.makedirs(WORK, exist_ok=True)
    if os.path.isdir(TREE):
        run(["git", "worktree", "remove", "--force", TREE], ROOT)
    r = run(["git", "worktree", "add", "--detach", TREE, "HEAD"], ROOT)
    if r.returncode != 0:
        sys.exit("git worktree add failed:\n" + r.stdout)
    # The tests find the shared scenes beside the repository; the worktree is not beside it.
    shared = os.path.join(os.path.dirname(ROOT), "shared", "scenes")
    r = run(["cmake", "-S", TREE, "-B", BUILD, "-G", "Ninja", "-DCMAKE_BUILD_TYPE=Release"], ROOT)
    if r.returncode != 0:
        sys.exit("cmake failed:\n" + r.stdout)
    return shared


def build(jobs):
    return run(["ninja", "-C", BUILD, f"-j{jobs}"], ROOT)


def ctest(jobs, shared, first=False, only=None):
    env = dict(os.environ, SYMPHONG_SCENES=shared, SYMPHONG_REQUIRE_SCENES="1")
    # --first: only the tests that count, stopping at the first that fails (ctest's -E takes the same regex);
    # `only`: the tests whose names begin with these and no others.
    extra = ["--stop-on-failure", "-E", NOT_INDEPENDENT.pattern] if first else []
    if only:
        extra += ["-R", "^(" + "|".join(re.escape(t) for t in only) + ")"]
    r = subprocess.run(["ctest", "--test-dir", BUILD, f"-j{jobs}", "--timeout", "900"] + extra, cwd=ROOT, stdout=subprocess.PIPE,
                       stderr=subprocess.STDOUT, text=True, env=env)
    # The list after "The following tests FAILED:"; a value-parameterized test's line carries a
    # "# GetParam() = ..." comment between its name and its status, so only the name is matched.
    tail = r.stdout.split("The following tests FAILED:", 1)[1] if "The following tests FAILED:" in r.stdout else ""
    failed = re.findall(r"^\s*\d+ - (\S+)", tail, re.M)
    return r.returncode, failed


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--only", default="", help="comma-separated bug names, run in this order")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--check", action="store_true", help="only check that every planted text is in the source once")
    ap.add_argument("--reuse", action="store_true",
                    help="keep the worktree and build an earlier run left (its commit, not HEAD) and skip the clean-tree "
                         "test run, which that run made; the commit is printed")
    ap.add_argument("--first", action="store_true",
                    help="with a bug planted, stop at the first failing test that counts (whether it is caught, not by what)")
    args = ap.parse_args()
    only = set(filter(None, args.only.split(",")))
    if args.check:
        return check_only(only)
    if args.reuse and os.path.isdir(TREE) and os.path.isdir(BUILD):
        shared = os.path.join(os.path.dirname(ROOT), "shared", "scenes")
        commit = run(["git", "rev-parse", "--short", "HEAD"], TREE).stdout.strip()
        print(f"reusing {TREE} at {commit} and its build; no clean-tree test run", file=sys.stderr, flush=True)
    else:
        shared = prepare()
        r = build(args.jobs)
        if r.returncode != 0:
            sys.exit("the clean tree does not build:\n" + r.stdout[-3000:])
        code, failed = ctest(args.jobs, shared)
        if code != 0:
            sys.exit("the clean tree fails tests: " + ", ".join(failed))
    rows, missed = [], 0
    order = [n.strip() for n in args.only.split(",") if n.strip()]
    for bug in sorted(BUGS, key=lambda b: order.index(b[0]) if b[0] in order else len(order)):  # --only's order
        name, what, rel, pairs = bug[0], bug[1], bug[2], replacements(*bug[3:5]) if len(bug) == 5 else bug[3]
        if only and name not in only:
            continue
        path = os.path.join(TREE, rel)
        with open(path) as f:
            text = f.read()
        planted = plant(text, pairs)
        if planted is None:
            rows.append((name, what, "STALE: the planted text is not in the source once"))
            print(f"{name}: {rows[-1][2]}", file=sys.stderr, flush=True)
            continue
        with open(path, "w") as f:
            f.write(planted)
        try:
            b = build(args.jobs)
            if b.returncode != 0:
                rows.append((name, what, "does not compile: " + b.stdout[-300:].replace("\n", " ")))
                print(f"{name}: {rows[-1][2]}", file=sys.stderr, flush=True)
                continue
            failed = []
            if args.first and FIRST_TRIED.get(name):
                code, failed = ctest(args.jobs, shared, True, FIRST_TRIED[name])
            if not failed:
                code, failed = ctest(args.jobs, shared, args.first)
            independent = [t for t in failed if not NOT_INDEPENDENT.match(t)]
            others = len(failed) - len(independent)
            if independent:
                rows.append((name, what, f"{len(independent)}: " + ", ".join(independent[:6]) +
                             (" ..." if len(independent) > 6 else "") + (f" (+{others} golden/docs)" if others else "")))
            else:
                rows.append((name, what, "MISSED" + (f" (only {others} golden/docs tests)" if others else "")))
                missed += 1
        finally:
            with open(path, "w") as f:
                f.write(text)
        print(f"{name}: {rows[-1][2]}", file=sys.stderr, flush=True)
    build(args.jobs)  # leave the tree clean and built
    print("| bug | what it simulates | failing tests |")
    print("|---|---|---|")
    for name, what, result in rows:
        print(f"| `{name}` | {what} | {result} |")
    return 1 if missed else 0


if __name__ == "__main__":
    sys.exit(main())
