#include "vlf/field/edge_table.hpp"

namespace vlf {

int EdgeTable::covered() const {
    int n = 0;
    for (int r = 0; r < rows; ++r) n += spans[r].width();
    return n;
}

}  // namespace vlf
