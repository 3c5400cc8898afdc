reset
read_model -i cylinder.smv
go
set oreg_justice_emptiness_bdd_algorithm EL_fwd
check_ltlspec
set oreg_justice_emptiness_bdd_algorithm EL_bwd
check_ltlspec -p "G (ctrl = out ->  F pos = extended)"
echo ==model-1==
echo -2 ==model-1==
reset
read_model -i err_syntax.smv
go
check_ltlspec
echo ==model-2==
echo -2 ==model-2==
reset
read_model -i err_undefined.smv
go
check_ltlspec
echo ==model-3==
echo -2 ==model-3==
reset
read_model -i light.smv
go
set prop_print_method name
check_ltlspec
echo ==model-4==
echo -2 ==model-4==
quit
