// parameters.cpp — (being written)
