// Tests written as XML (<test type="..."> roots, Nori's format). `nori file.xml` runs
// a test root and exits 0 when it passes, 1 when it fails.
#pragma once

#include <nori/object.h>

#include <functional>

namespace nori {

/// How a test run leaves its pictures (χ² tests draw observed | expected | difference).
struct TestOptions {
    std::string pictureFolder; ///< where pictures go; empty: no pictures
    bool allPictures = false;  ///< a picture of every case, not only of failing ones
    /// Called with each picture's file and title once it is written (the preview shows it).
    std::function<void(const std::string &file, const std::string &title)> pictureWritten;
};

class Test : public NoriObject {
public:
    static constexpr EClassType kClassType = ETest;

    /// Runs the test, printing its report to stdout; returns whether it passed.
    virtual bool run(const TestOptions &options = {}) = 0;

    EClassType getClassType() const override { return kClassType; }
};

} // namespace nori
