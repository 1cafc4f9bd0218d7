// scene_loader.cpp — (being written)
