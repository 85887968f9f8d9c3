// The estimator and sampler tables (estimators/registry.h, sampling/sampler_registry.h): every entry
// creates what it names, its traits agree with what the created object says of itself, and the names,
// help text and errors derived from the tables are the ones the CLI has always printed.
#include "estimators/registry.h"
#include "sampling/sampler_registry.h"

#include <gtest/gtest.h>

#include <set>

using namespace symphong;

TEST(EstimatorTable, EveryEntryCreatesWhatItNamesWithItsTraits) {
    std::set<std::string_view> names;
    for (const EstimatorEntry& e : estimatorTable()) {
        SCOPED_TRACE(std::string(e.name));
        EXPECT_TRUE(names.insert(e.name).second) << "duplicate name";
        const auto est = e.create(EstimatorOptions{});
        ASSERT_TRUE(est);
        EXPECT_EQ(est->name(), e.name);
        EXPECT_EQ(est->requiredSampler(), e.traits.ownSampler);
        EXPECT_EQ(est->combinesWithLightSampling(), e.traits.hasDensity);
        // A set estimator returns a whole set per call in branch mode (the default) and one entry per
        // call in spread mode; the others never return sets.
        EXPECT_EQ(est->returnsSets(), e.traits.setEstimator);
        if (e.traits.setEstimator) {
            EstimatorOptions spread;
            spread.symmetricMode = SymmetricMode::Spread;
            EXPECT_FALSE(e.create(spread)->returnsSets());
        }
        EXPECT_EQ(findEstimator(e.name), &e);
        EXPECT_EQ(hasSymmetricModes(e.name), e.traits.setEstimator);
    }
    EXPECT_EQ(names.size(), estimatorNames().size());
    EXPECT_EQ(findEstimator("bogus"), nullptr);
    EXPECT_EQ(yardstickEstimator(), "phong");
}

TEST(EstimatorTable, ParametersAreCheckedByTheEstimatorsThatReadThem) {
    EstimatorOptions badN;
    badN.symmetricN = 0;
    EXPECT_THROW(makeEstimator("symmetric", badN), std::invalid_argument);
    EXPECT_THROW(makeEstimator("paper", badN), std::invalid_argument);
    EXPECT_NO_THROW(makeEstimator("phong", badN)) << "phong has no N'";
    EstimatorOptions badOrbit;
    badOrbit.symmetricOrbit = 3;
    try {
        makeEstimator("symmetric-mix", badOrbit);
        FAIL() << "orbit 3 accepted";
    } catch (const std::invalid_argument& e) {
        EXPECT_STREQ(e.what(), "--symmetric-orbit 3 is not one of 1, 2, 4, 8");
    }
    EXPECT_NO_THROW(makeEstimator("symmetric", badOrbit)) << "symmetric has no orbit";
    // The trait that the study's orbit variants go by: exactly the estimators that check the orbit.
    for (const EstimatorEntry& e : estimatorTable()) {
        bool refused = false;
        try {
            e.create(badOrbit);
        } catch (const std::invalid_argument&) {
            refused = true;
        }
        EXPECT_EQ(refused, e.traits.takesOrbit) << e.name;
    }
    try {
        makeEstimator("bogus");
        FAIL();
    } catch (const std::invalid_argument& e) {
        EXPECT_STREQ(
            e.what(),
            "unknown estimator 'bogus' (valid: uniform, cosine, stratified, phong, paper, symmetric, symmetric-shifted, symmetric-mix)");
    }
}

TEST(EstimatorTable, HelpHasOneAlignedLinePerEntry) {
    const std::string help = estimatorHelp();
    EXPECT_EQ(help.rfind("uniform    - uniform hemisphere directions", 0), 0u) << help;
    EXPECT_NE(help.find("\nsymmetric-shifted - as symmetric"), std::string::npos);
    EXPECT_NE(help.find("lobe vs\n             diffuse by albedo"), std::string::npos);
    EXPECT_NE(help.back(), '\n');
}

TEST(SamplerTable, EveryEntryCreatesWhatItNames) {
    for (const SamplerEntry& e : samplerTable()) {
        SCOPED_TRACE(std::string(e.name));
        const auto s = e.create(16, 3);
        EXPECT_EQ(s->name(), e.name);
        EXPECT_EQ(s->samplesPerPixel(), 16u);
        EXPECT_EQ(s->seed(), 3u);
        EXPECT_EQ(makeSampler(e.name, 16, 3)->name(), e.name);
    }
    EXPECT_TRUE(isIndependentSampler("independent"));
    EXPECT_FALSE(isIndependentSampler("sobol"));
    EXPECT_EQ(samplerHelp(),
              "independent - independent uniform numbers (PCG32 streams)\n"
              "stratified  - jittered strata (correlated multi-jittered) in every dimension pair, any spp\n"
              "sobol       - Owen-scrambled Sobol' (0,2)-sequence in every dimension pair (the default)");
    EXPECT_THROW(makeSampler("halton", 4, 1), std::invalid_argument);
}
