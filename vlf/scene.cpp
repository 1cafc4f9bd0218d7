// scene.cpp — (being written)
