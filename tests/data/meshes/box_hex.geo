// Box 1 x 0.5 x 0.4 (volume 0.2): a structured 3 x 2 x 2 hexahedral mesh.
// Groups: body (volume), clamp (x = 0), tip (x = 1).
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 1, 0.5, 0.4};
Transfinite Curve{:} = 3;
Transfinite Curve{9, 10, 11, 12} = 4;
Transfinite Surface{:};
Recombine Surface{:};
Transfinite Volume{1};
Physical Volume("body", 1) = {1};
Physical Surface("clamp", 2) = {1};
Physical Surface("tip", 3) = {2};
