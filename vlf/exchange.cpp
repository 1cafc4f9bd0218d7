// exchange.cpp — (being written)
