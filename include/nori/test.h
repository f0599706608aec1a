// Tests written as XML (<test type="..."> roots, Nori's format). `nori file.xml` runs
// a test root and exits 0 when it passes, 1 when it fails.
#pragma once

#include <nori/object.h>

namespace nori {

class Test : public NoriObject {
public:
    static constexpr EClassType kClassType = ETest;

    /// Runs the test, printing its report to stdout; returns whether it passed.
    virtual bool run() = 0;

    EClassType getClassType() const override { return kClassType; }
};

} // namespace nori
