// rotation.cpp — (being written)
