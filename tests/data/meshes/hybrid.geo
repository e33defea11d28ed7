// Unit cube (volume 1) with every 3D element type of order 1:
// z in [0, 0.5]: a tri/quad surface mesh extruded in 1 layer with
// Recombine -> prisms (from triangles) and hexahedra (from quadrangles);
// z in [0.5, 1]: tetrahedra, with pyramids on the quadrangles of the shared face.
// Groups: lower, upper (volumes), bottom (z = 0), top (z = 1).
SetFactory("Built-in");
h = 0.8;
Point(1) = {0, 0, 0, h}; Point(2) = {0.5, 0, 0, h}; Point(3) = {1, 0, 0, h};
Point(4) = {1, 1, 0, h}; Point(5) = {0.5, 1, 0, h}; Point(6) = {0, 1, 0, h};
Line(1) = {1, 2}; Line(2) = {2, 5}; Line(3) = {5, 6}; Line(4) = {6, 1};
Line(5) = {2, 3}; Line(6) = {3, 4}; Line(7) = {4, 5};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Curve Loop(2) = {5, 6, 7, -2}; Plane Surface(2) = {2};
Transfinite Curve{5, 6, 7, 2} = 3;
Transfinite Surface{2};
Recombine Surface{2};
lower[] = Extrude {0, 0, 0.5} { Surface{1, 2}; Layers{1}; Recombine; };
// lower[0] top of surface 1, lower[1] volume 1, lower[6] top of surface 2, lower[7] volume 2
upper[] = Extrude {0, 0, 0.5} { Surface{lower[0], lower[6]}; };
Physical Volume("lower", 1) = {lower[1], lower[7]};
Physical Volume("upper", 2) = {upper[1], upper[7]};
Physical Surface("bottom", 3) = {1, 2};
Physical Surface("top", 4) = {upper[0], upper[6]};
