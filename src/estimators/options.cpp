#include "estimators/options.h"

namespace symphong {

const schema::Schema<EstimatorOptions>& estimatorOptionsSchema() {
    using F = schema::Field<EstimatorOptions>;
    static const schema::Schema<EstimatorOptions> fields = [] {
        schema::Schema<EstimatorOptions> s;
        s.push_back(F("symmetric_n", "--symmetric-n", "N': (u,v) points per piece for paper, symmetric, symmetric-shifted",
                      schema::member(&EstimatorOptions::symmetricN))
                        .range(1, 4096));
        s.push_back(F("paper_refined", "--paper-refined", "paper: use the conclusion's finer lobe normalisation instead of Eq. (6)'s",
                      schema::member(&EstimatorOptions::paperRefined)));
        s.push_back(F("symmetric_orbit", "--symmetric-orbit",
                      "symmetric-mix: symmetric copies of one point used together, traced from one camera sample (branch) or "
                      "spread over consecutive camera samples (spread): 1, 2, 4 or 8",
                      schema::member(&EstimatorOptions::symmetricOrbit))
                        .among({1, 2, 4, 8}));
        s.push_back(F("symmetric_mode", "--symmetric-mode",
                      "paper, symmetric*: 'branch' (a camera sample traces the whole set from its first hit; symmetric-mix: its orbit "
                      "of --symmetric-orbit copies) or 'spread' (the set is spread over a pixel's camera samples, one piece or copy "
                      "each) [default: branch]",
                      schema::TextAccess<EstimatorOptions>{
                          [](const EstimatorOptions& o) { return std::string(symmetricModeName(o.symmetricMode)); },
                          [](EstimatorOptions& o, const std::string& name) { o.symmetricMode = parseSymmetricMode(name); }})
                        .type("MODE"));
        return s;
    }();
    return fields;
}

}  // namespace symphong
