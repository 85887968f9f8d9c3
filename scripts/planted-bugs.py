#!/usr/bin/env python3
"""Plants known bugs in a copy of the source, one at a time, and runs the test suite after each.

Usage: python3 scripts/planted-bugs.py [--only NAME,...] [--jobs N]

For every bug below it applies one exact text replacement to a git worktree of HEAD (beside the
checkout, as ../<checkout>-planted, so that scenes referring to ../shared resolve), builds it under
build/planted/, runs `ctest`, records which tests failed, and reverts the file. The table it
prints is the one in docs/testing.md ("Planted bugs"). A bug whose text is no longer in the source is
reported as STALE (the code moved; update the replacement), never silently skipped. A bug that no test
catches is reported as MISSED and makes the script exit 1.
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

# name, what it simulates, file, exact old text, new text
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
     "powerHeuristic(s.pdf, estimatorMisPdf(sc, wiLocal))", "powerHeuristic(estimatorMisPdf(sc, wiLocal), s.pdf)"),
    ("roulette-unweighted", "Russian roulette survivors not divided by the survival probability", "src/render/path_tracer.cpp",
     "return L + s.weight * radiance(origin, wi, depth + 1, nextPath, s.misPdf, next, pc) / survive;",
     "return L + s.weight * radiance(origin, wi, depth + 1, nextPath, s.misPdf, next, pc);"),
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
     "src/sampling/sampler.cpp",
     "Point2 SobolSampler::value2D(std::uint64_t key, std::uint32_t index, std::uint32_t count, std::uint64_t dim) const {\n    const std::uint64_t h = mixSeed(key, 2 * dim);",
     "Point2 SobolSampler::value2D(std::uint64_t key, std::uint32_t index, std::uint32_t count, std::uint64_t dim) const {\n    const std::uint64_t h = mixSeed(0 * key, 2 * dim);"),
    ("cutout-shadow-rays", "a cut-out that camera rays see but shadow rays ignore", "src/accel/accel.cpp",
     "        rtcSetGeometryOccludedFilterFunction(geom, cutOutFilter);\n", "\n"),
    ("nested-node-transform", "a file whose nodes nest: the parent's transform dropped", "src/scene/assimp_loader.cpp",
     "world * node->mChildren[i]->mTransformation", "node->mChildren[i]->mTransformation"),
]


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


def ctest(jobs, shared):
    env = dict(os.environ, SYMPHONG_SCENES=shared, SYMPHONG_REQUIRE_SCENES="1")
    r = subprocess.run(["ctest", "--test-dir", BUILD, f"-j{jobs}", "--timeout", "900"], cwd=ROOT, stdout=subprocess.PIPE,
                       stderr=subprocess.STDOUT, text=True, env=env)
    # The list after "The following tests FAILED:"; a value-parameterized test's line carries a
    # "# GetParam() = ..." comment between its name and its status, so only the name is matched.
    tail = r.stdout.split("The following tests FAILED:", 1)[1] if "The following tests FAILED:" in r.stdout else ""
    failed = re.findall(r"^\s*\d+ - (\S+)", tail, re.M)
    return r.returncode, failed


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--only", default="", help="comma-separated bug names")
    ap.add_argument("--jobs", type=int, default=2)
    args = ap.parse_args()
    only = set(filter(None, args.only.split(",")))
    shared = prepare()
    r = build(args.jobs)
    if r.returncode != 0:
        sys.exit("the clean tree does not build:\n" + r.stdout[-3000:])
    code, failed = ctest(args.jobs, shared)
    if code != 0:
        sys.exit("the clean tree fails tests: " + ", ".join(failed))
    rows, missed = [], 0
    for name, what, rel, old, new in BUGS:
        if only and name not in only:
            continue
        path = os.path.join(TREE, rel)
        with open(path) as f:
            text = f.read()
        if text.count(old) != 1:
            rows.append((name, what, "STALE: the planted text is not in the source once"))
            print(f"{name}: {rows[-1][2]}", file=sys.stderr, flush=True)
            continue
        with open(path, "w") as f:
            f.write(text.replace(old, new))
        try:
            b = build(args.jobs)
            if b.returncode != 0:
                rows.append((name, what, "does not compile: " + b.stdout[-300:].replace("\n", " ")))
                print(f"{name}: {rows[-1][2]}", file=sys.stderr, flush=True)
                continue
            code, failed = ctest(args.jobs, shared)
            if failed:
                rows.append((name, what, f"{len(failed)}: " + ", ".join(failed[:6]) + (" ..." if len(failed) > 6 else "")))
            else:
                rows.append((name, what, "MISSED"))
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
