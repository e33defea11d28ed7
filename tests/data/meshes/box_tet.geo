// Box 1 x 0.5 x 0.4 (volume 0.2) meshed with tetrahedra.
// Groups: body (volume), clamp (x = 0), tip (x = 1), edge (a curve),
// and an unnamed physical point (tag 7) at the origin.
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 1, 0.5, 0.4};
Mesh.MeshSizeMin = 0.5;
Mesh.MeshSizeMax = 0.5;
Physical Volume("body", 1) = {1};
Physical Surface("clamp", 2) = {1};
Physical Surface("tip", 3) = {2};
Physical Curve("edge", 5) = {1};
Physical Point(7) = {1};
