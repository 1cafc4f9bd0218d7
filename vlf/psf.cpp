// psf.cpp — (being written)
