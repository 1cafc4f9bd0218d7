// progress.cpp — (being written)
