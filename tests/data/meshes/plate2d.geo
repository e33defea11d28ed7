// L-shaped plate in the plane z = 0 (area 3): the rectangle [0,2] x [0,1]
// recombined into quadrangles (partially, so some triangles may remain)
// and the square [0,1] x [1,2] meshed with triangles.
// Groups: steel (lower rectangle), gel (upper square), clamp (x = 0), load (y = 2).
SetFactory("Built-in");
h = 0.5;
Point(1) = {0, 0, 0, h}; Point(2) = {2, 0, 0, h}; Point(3) = {2, 1, 0, h};
Point(4) = {1, 1, 0, h}; Point(5) = {0, 1, 0, h}; Point(6) = {1, 2, 0, h};
Point(7) = {0, 2, 0, h};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 5};
Line(5) = {5, 1}; Line(6) = {4, 6}; Line(7) = {6, 7}; Line(8) = {7, 5};
Curve Loop(1) = {1, 2, 3, 4, 5}; Plane Surface(1) = {1};
Curve Loop(2) = {-4, 6, 7, 8}; Plane Surface(2) = {2};
Recombine Surface{1};
Physical Surface("steel", 1) = {1};
Physical Surface("gel", 2) = {2};
Physical Curve("clamp", 3) = {5, 8};
Physical Curve("load", 4) = {7};
