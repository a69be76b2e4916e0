0 BEGIN PGM CONTOUR MM
1 ; A contour pocket wall in three passes, written from the iTNC 530 User's Manual, Conversational
2 ; Programming (Heidenhain 670388): the example "Circular movements, Cartesian" (L, CR, CT about the
3 ; outline 0-100 mm), without its radius compensation, APPR/DEP and RND (not read here: this is the
4 ; tool-centre path), repeated with "Program section repeats" (LBL 1 ... CALL LBL 1 REP 2), a
5 ; "Subprogram" (LBL 2 ... LBL 0 after M2) and a full circle about the pole CC. Twin: CONTOUR_linuxcnc.ngc.
6 BLK FORM 0.1 Z X+0 Y+0 Z-20
7 BLK FORM 0.2 X+100 Y+100 Z+0
8 TOOL CALL 1 Z S4000 F300
9 Q1 = +2.5
10 * - OUTLINE IN THREE PASSES
11 L Z+50 R0 FMAX
12 L X+5 Y+5 R0 FMAX M3
13 L Z+0 R0 F1000
14 LBL 1
15 L IZ-Q1 R0 F200
16 L X+5 Y+85 R0 FAUTO
17 L X+30
18 CR X+70 Y+95 R+30 DR-
19 L X+95
20 L X+95 Y+40
21 CT X+40 Y+5
22 L X+5
23 CALL LBL 1 REP 2
24 L Z+50 R0 FMAX
25 * - HOLES AND A CIRCLE
26 L X+20 Y+20 R0 FMAX
27 CALL LBL 2
28 L X+80 Y+20 R0 FMAX
29 CALL LBL 2
30 CC X+50 Y+50
31 L X+75 Y+50 R0 FMAX
32 L Z-2 R0 F200
33 C X+75 Y+50 DR+ F300
34 CR X+50 Y+25 R-25 DR+
35 L Z+50 R0 FMAX M2
36 LBL 2
37 L Z+2 R0 FMAX
38 L IZ-6 R0 F100
39 L IZ+6 R0 FMAX
40 LBL 0
41 END PGM CONTOUR MM
