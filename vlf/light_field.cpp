// light_field.cpp — (being written)
