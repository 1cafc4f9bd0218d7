// edge_table.cpp — (being written)
