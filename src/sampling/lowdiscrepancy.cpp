#include <nori/lowdiscrepancy.h>

namespace nori {

double radicalInverse(int base, uint64_t index) {
    const double inverseBase = 1.0 / base;
    double inverseBasePower = 1.0, reversed = 0.0;
    while (index > 0) {
        const uint64_t next = index / base;
        const uint64_t digit = index - next * base;
        inverseBasePower *= inverseBase;
        reversed += static_cast<double>(digit) * inverseBasePower;
        index = next;
    }
    return reversed < 1.0 ? reversed : 0x1.fffffffffffffp-1;
}

} // namespace nori
