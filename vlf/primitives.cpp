// primitives.cpp — (being written)
