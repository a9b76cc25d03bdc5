-- | Runtime errors (Table 5-3), the diagnostic band (MT-DIAG) and the CHF
-- parameters of F modules (MT-PARAM).
module ExecutionErrorSpec (spec) where

import Execution.Build
import qualified Data.Map.Strict as M
import Stref.Checked
import Stref.Diagnostics
import Stref.Execution
import Stref.Operands
import Stref.Policy
import Stref.Types
import Stref.Values
import Test.Hspec

x :: Var
x = dataVar "X" (Basic INT) 0

m10 :: Var
m10 = mappedVar "M" (Basic INT) "%M0010"

-- | A module whose mapped variables are checked before the body, which
-- would write %M0010 := 1.
mappedOnly :: [Var] -> CModule
mappedOnly vs = build spec0 {msVars = m10 : vs, msBody = [assign 5 m10 (int 1)]}

errorOf :: Policies -> CModule -> (PlcState, CallResult)
errorOf = runOnce

spec :: Spec
spec = describe "Execution: runtime errors" $ do
  describe "undeclared mapped operands, before the first line (MT-MAP-8, A2)" $ do
    let check name var expected = it name $ do
          let (st, r) = errorOf mastertoolXE (mappedOnly [var])
          crError r `shouldBe` Just expected
          bandOf st `shouldBe` errorBandOf expected
          crOutputs r `shouldBe` (False, False, False)
          operandValue st "%M0010" INT `shouldBe` VInt 0 -- the body did not run
        errorBandOf e = map toInteger (errorBand e)
    -- the default layout declares %M0000..%M1999, %E/%S 0..15, %A 0..63,
    -- %I/%F 0..99, tables %TM0010 (200), %TM0030 (100), %TI0010 (50), %TF0010 (50)
    check "2000 for %M2500: kind 0, address 2500" (mappedVar "Z" (Basic INT) "%M2500") (RuntimeError 2000 0 (0, 2500, 0))
    check "2000 for %E0020: kind 8" (mappedVar "Z" (Basic BYTE) "%E0020") (RuntimeError 2000 0 (8, 20, 0))
    check "2000 for %S0016: kind 8" (mappedVar "Z" (Basic BYTE) "%S0016") (RuntimeError 2000 0 (8, 16, 0))
    check "2000 for %A0070.1: kind 9" (mappedVar "Z" (Basic BOOL) "%A0070.1") (RuntimeError 2000 0 (9, 70, 0))
    check "2000 for %I0100: kind 1" (mappedVar "Z" (Basic DINT) "%I0100") (RuntimeError 2000 0 (1, 100, 0))
    check "2000 for %F0100: kind 4" (mappedVar "Z" (Basic REAL) "%F0100") (RuntimeError 2000 0 (4, 100, 0))
    -- ARRAY[1..4] AT %M1998 covers %M1998..%M2001; %M2000 is the first missing
    check "2000 for the first missing element of a mapped array (MT-MAP-10)" (mappedVar "Z" (Array 1 4 INT) "%M1998") (RuntimeError 2000 0 (0, 2000, 0))
    check "2001 for a table that is not declared: %TM0020" (mappedVar "Z" (Basic INT) "%TM0020[0]") (RuntimeError 2001 0 (0, 20, 0))
    check "2001 with kind 4 for %TF0011" (mappedVar "Z" (Basic REAL) "%TF0011[0]") (RuntimeError 2001 0 (4, 11, 0))
    -- ARRAY[1..2] AT %TM0010[199] covers positions 199 and 200; 200 is missing
    check "2002 for a position past the table's end" (mappedVar "Z" (Array 1 2 INT) "%TM0010[199]") (RuntimeError 2002 0 (0, 10, 200))
    check "2002 with kind 1 for %TI0010[50]" (mappedVar "Z" (Basic DINT) "%TI0010[50]") (RuntimeError 2002 0 (1, 10, 50))
    it "writes the line of error-line-before-start (-1 for the PT revision)" $
      fmap reLine (crError (snd (errorOf mastertoolXE {pErrorLineBeforeStart = -1} (mappedOnly [mappedVar "Z" (Basic INT) "%M2500"]))))
        `shouldBe` Just (-1)
    it "uses the configuration: %M2500 is fine when 3000 %M are declared" $ do
      let cfg = defaultPlcConfig {plcSimple = M.insert KM 3000 (plcSimple defaultPlcConfig)}
          (_, r) = runWith mastertoolXE cfg defaultCallInput initialPlcState (mappedOnly [mappedVar "Z" (Basic INT) "%M2500"])
      crError r `shouldBe` Nothing

  describe "errors in the body (MT-EXEC-8, MT-SIG-5, MT-DIAG-2)" $ do
    -- line 3 writes %M0010 := 7, line 4 divides by zero, line 5 never runs
    let body =
          [ assign 2 out2 (bool True)
          , assign 3 m10 (int 7)
          , assign 4 x (divide 4 (int 1) (int 0))
          , assign 5 m10 (int 8)
          ]
        (st, r) = errorOf mastertoolXE (build spec0 {msVars = [m10, x], msBody = body})
    it "2020 with the line of the division" $ crError r `shouldBe` Just (runtimeError errDivisionByZero 4)
    it "writes [line, code, 0, 0, 0] into the band" $ bandOf st `shouldBe` [4, 2020, 0, 0, 0]
    it "clears OUTPUT1 and keeps OUTPUT2 as written" $ crOutputs r `shouldBe` (False, True, False)
    it "keeps operand writes made before the error and stops at once" $ operandValue st "%M0010" INT `shouldBe` VInt 7
    let v = dataVar "V" (Array 1 3 INT) 10
        indexed p ix = errorOf p (build spec0 {msVars = [v, x], msBody = [assignAt 7 v (dint ix) (int 1), assign 8 x (rdAt 8 v (dint 0))]})
    it "2015 with the line of the index, for an index above the upper bound (MT-ARR-8, A23)" $ do
      let (st', r') = indexed mastertoolXE 4
      (crError r', bandOf st') `shouldBe` (Just (runtimeError errIndex 7), [7, 2015, 0, 0, 0])
    it "2015 for an index below the lower bound when reading" $
      crError (snd (indexed mastertoolXE 2)) `shouldBe` Just (runtimeError errIndex 8)
    it "index-out-of-range = clamp: V[4] writes V[3], V[0] reads V[1]" $ do
      let r' = snd (indexed mastertoolXE {pIndexOutOfRange = IndexClamp} 4)
      (crError r', varValue "P.V[3]" r', varValue "P.X" r') `shouldBe` (Nothing, Just (VInt 1), Just (VInt 0))
    it "index-out-of-range = trap: a trap at the index's line" $
      crError (snd (indexed mastertoolXE {pIndexOutOfRange = IndexTrap} 4)) `shouldBe` Just (runtimeError trapIndex 7)
    it "2030 when the step budget runs out" $ do
      let (st', r') = errorOf mastertoolXE {pStepBudget = 500} (build spec0 {msVars = [x], msBody = [SWhile 6 (bool True) []]})
      (crError r', bandOf st', crOutputs r') `shouldBe` (Just (runtimeError errExecutionTime 6), [6, 2030, 0, 0, 0], (False, False, False))
    it "a later successful call writes the no-error band again" $ do
      let cm b = build spec0 {msVars = [x], msBody = [assign 4 x (divide 4 (int 1) (int b))]}
          (st1, _) = runOnce mastertoolXE (cm 0)
          (st2, _) = runWith mastertoolXE defaultPlcConfig defaultCallInput st1 (cm 1)
      (bandOf st1, bandOf st2) `shouldBe` ([4, 2020, 0, 0, 0], [-32768, 0, 0, 0, 0])

  describe "F-module parameters (MT-PARAM)" $ do
    let a = dataVar "A" (Basic INT) 20 -- VAR_INPUT
        bIO = dataVar "B" (Basic INT) 21 -- VAR_IN_OUT
        c = dataVar "C" (Basic INT) 22 -- VAR_OUTPUT
        alias = mappedVar "MB" (Basic INT) "%M0011"
        y = dataVar "Y" (Basic INT) 1
        fmod extra =
          build
            spec0
              { msVars = [alias, x, y]
              , msInputs = [a]
              , msInOuts = [bIO]
              , msOutputs = [c]
              , msBody =
                  [ assign 2 bIO (add 2 (rd bIO) (rd a))
                  , assign 3 y (rd alias)
                  , assign 4 c (add 4 (rd a) (rd a))
                  ]
                    ++ extra
              }
        mem0 = writeOperand (op "%M0011") (VInt 4) (writeOperand (op "%M0010") (VInt 3) emptyMemory)
        callWith ins outs extra =
          runWith mastertoolXE defaultPlcConfig defaultCallInput {ciChfIn = ins, ciChfOut = outs} initialPlcState {psMemory = mem0} (fmod extra)
        arg = ChfOperand . op
        okCall = callWith [arg "%M0010", arg "%M0011"] [arg "%M0012"] []
    it "copies VAR_IN_OUT back and writes VAR_OUTPUT on success (MT-PARAM-5): B = 4 + 3, C = 3 + 3" $ do
      let (st, r) = okCall
      (crError r, operandValue st "%M0011" INT, operandValue st "%M0012" INT) `shouldBe` (Nothing, VInt 7, VInt 6)
    it "works on a local copy: an alias of the in-out operand still reads the old value" $
      varValue "P.Y" (snd okCall) `shouldBe` Just (VInt 4)
    it "copies nothing back after a runtime error (A19)" $ do
      let (st, r) = callWith [arg "%M0010", arg "%M0011"] [arg "%M0012"] [assign 9 x (divide 9 (int 1) (int 0))]
      (crError r, operandValue st "%M0011" INT, operandValue st "%M0012" INT) `shouldBe` (Just (runtimeError 2020 9), VInt 4, VInt 0)
    it "copies back after a RETURN (MT-STMT-5, A19)" $ do
      let (st, _) = callWith [arg "%M0010", arg "%M0011"] [arg "%M0012"] [SReturn 9]
      operandValue st "%M0011" INT `shouldBe` VInt 7
    it "takes a %KM constant into a VAR_INPUT" $ do
      let (st, _) = callWith [ChfConstant KMConst 5, arg "%M0011"] [arg "%M0012"] []
      operandValue st "%M0012" INT `shouldBe` VInt 10
    describe "a %KM constant measured against a USINT parameter (MT-PARAM-7)" $ do
      let uv = dataVar "UV" (Basic USINT) 20
          res = dataVar "RES" (Basic USINT) 21
          umod = build spec0 {msInputs = [uv], msOutputs = [res], msBody = [assign 2 res (rd uv)]}
          callU k = runWith mastertoolXE defaultPlcConfig defaultCallInput {ciChfIn = [ChfConstant KMConst k], ciChfOut = [arg "%E0001"]} initialPlcState umod
      it "200 fits" $ operandValue (fst (callU 200)) "%E0001" USINT `shouldBe` VUSInt 200
      it "300 does not: 2008 with comp 1 = 1" $ crError (snd (callU 300)) `shouldBe` Just (RuntimeError 2008 0 (1, 0, 0))
    let failing name ins outs expected = it name $ do
          let (st, r) = callWith ins outs []
          crError r `shouldBe` Just expected
          bandOf st `shouldBe` map toInteger (errorBand expected)
          operandValue st "%M0011" INT `shouldBe` VInt 4
    failing "2009 for a wrong number of inputs" [arg "%M0010"] [arg "%M0012"] (runtimeError 2009 0)
    failing "2010 for a wrong number of outputs" [arg "%M0010", arg "%M0011"] [] (runtimeError 2010 0)
    failing "2003 for an input of an incompatible type (%F to INT), comp 1 = 1" [arg "%F0001", arg "%M0011"] [arg "%M0012"] (RuntimeError 2003 0 (1, 0, 0))
    failing "2003 for a constant to a VAR_IN_OUT (MT-PARAM-7), comp 1 = 2" [arg "%M0010", ChfConstant KMConst 1] [arg "%M0012"] (RuntimeError 2003 0 (2, 0, 0))
    failing "2003 for a %KF constant to an INT" [ChfConstant KFConst 1.5, arg "%M0011"] [arg "%M0012"] (RuntimeError 2003 0 (1, 0, 0))
    failing "2003 for a partial operand (a bit)" [arg "%M0010.1", arg "%M0011"] [arg "%M0012"] (RuntimeError 2003 0 (1, 0, 0))
    failing "2008 for a constant too large for INT" [ChfConstant KMConst 40000, arg "%M0011"] [arg "%M0012"] (RuntimeError 2008 0 (1, 0, 0))
    failing "2005 for an undeclared input operand" [arg "%M2500", arg "%M0011"] [arg "%M0012"] (RuntimeError 2005 0 (1, 0, 0))
    failing "2004 for an output of an incompatible type (%I to INT)" [arg "%M0010", arg "%M0011"] [arg "%I0001"] (RuntimeError 2004 0 (1, 0, 0))
    failing "2006 for an undeclared output operand" [arg "%M0010", arg "%M0011"] [arg "%M2500"] (RuntimeError 2006 0 (1, 0, 0))
    describe "array parameters" $ do
      let arr = dataVar "AR" (Array 1 3 INT) 30
          total = dataVar "T" (Basic INT) 2
          amod =
            build
              spec0
                { msVars = [total]
                , msInputs = [arr]
                , msBody = [assign 2 total (add 2 (add 2 (rdAt 2 arr (dint 1)) (rdAt 2 arr (dint 2))) (rdAt 2 arr (dint 3)))]
                }
          mem = foldr (\(o, v) -> writeOperand (op o) (VInt v)) emptyMemory [("%TM0030[0]", 1), ("%TM0030[1]", 2), ("%TM0030[2]", 4), ("%M0100", 10), ("%M0101", 20), ("%M0102", 40)]
          callA ins = runWith mastertoolXE defaultPlcConfig defaultCallInput {ciChfIn = ins} initialPlcState {psMemory = mem} amod
      it "takes a whole table: 1 + 2 + 4" $ varValue "P.T" (snd (callA [ChfTable TM 30])) `shouldBe` Just (VInt 7)
      it "takes a block of simple operands: 10 + 20 + 40" $ varValue "P.T" (snd (callA [ChfOperand (op "%M0100")])) `shouldBe` Just (VInt 70)
      it "2011 for a table with too few positions (%TM0010[198..200])" $
        crError (snd (callA [ChfOperand (op "%TM0010[198]")])) `shouldBe` Just (RuntimeError 2011 0 (1, 0, 0))
      it "2005 for a block that runs past the declared %M" $
        crError (snd (callA [ChfOperand (op "%M1998")])) `shouldBe` Just (RuntimeError 2005 0 (1, 0, 0))
      it "2005 for a table that is not declared" $
        crError (snd (callA [ChfTable TM 20])) `shouldBe` Just (RuntimeError 2005 0 (1, 0, 0))
      it "2003 for a constant to an array" $
        crError (snd (callA [ChfConstant KMConst 1])) `shouldBe` Just (RuntimeError 2003 0 (1, 0, 0))
