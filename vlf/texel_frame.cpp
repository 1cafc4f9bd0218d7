// texel_frame.cpp — (being written)
