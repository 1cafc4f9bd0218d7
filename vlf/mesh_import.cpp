// mesh_import.cpp — (being written)
