// direction_set.cpp — (being written)
