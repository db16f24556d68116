// A plate with a hole, 40 x 20 x 10 mm, a hole of radius 5 mm through its thickness
// at (20, 10): OpenCASCADE solid, lengths in mm (the deck's scale: 1e-3 m per mm).
// Physical groups: the volume "part" and the end faces "left" (x = 0), "right" (x = 40).
// CAD volume: 40 * 20 * 10 - pi * 5^2 * 10 = 7214.6018 mm^3.
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 40, 20, 10};
Cylinder(2) = {20, 10, -1, 0, 0, 12, 5};
BooleanDifference(3) = { Volume{1}; Delete; }{ Volume{2}; Delete; };
eps = 1e-6;
left() = Surface In BoundingBox{-eps, -eps, -eps, eps, 20 + eps, 10 + eps};
right() = Surface In BoundingBox{40 - eps, -eps, -eps, 40 + eps, 20 + eps, 10 + eps};
Physical Volume("part") = {3};
Physical Surface("left") = {left()};
Physical Surface("right") = {right()};
