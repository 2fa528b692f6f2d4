this is a CSV, not a grid
t_s,x
0,1
